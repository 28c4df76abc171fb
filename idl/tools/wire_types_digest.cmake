# Writes the digest of the wire types a session's recorded bytes are made of into a C++ source,
# at build time:
#   cmake -DROOTS="a.idl;b.idl" -DSEARCH="dir1;dir2" -DOUT=file.cpp -P wire_types_digest.cmake
# The digest covers each root IDL file and every file it includes (searched for in SEARCH), in a
# fixed order, with comments and blank space left out: a change of a type, a field or an
# annotation changes it; a comment does not. It is the first 16 hex digits of the SHA-256.
cmake_minimum_required(VERSION 3.16)  # IN_LIST, list(POP_FRONT) in script mode
set(pending ${ROOTS})
set(seen)
while(pending)
  list(POP_FRONT pending file)
  get_filename_component(name "${file}" NAME)
  if(name IN_LIST seen)
    continue()
  endif()
  list(APPEND seen "${name}")
  file(READ "${file}" text)
  string(REGEX MATCHALL "#include \"[^\"]+\"" includes "${text}")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "#include \"([^\"]+)\"" "\\1" included "${line}")
    set(found "")
    foreach(dir IN LISTS SEARCH)
      if(NOT found AND EXISTS "${dir}/${included}")
        set(found "${dir}/${included}")
      endif()
    endforeach()
    if(NOT found)
      message(FATAL_ERROR "${file} includes ${included}, found in none of ${SEARCH}")
    endif()
    list(APPEND pending "${found}")
  endforeach()
  set(text_of_${name} "${text}")
endwhile()
list(SORT seen)
set(all "")
foreach(name IN LISTS seen)
  set(text "${text_of_${name}}")
  string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")  # /* ... */
  string(REGEX REPLACE "//[^\n]*" "" text "${text}")                   # // ...
  string(REGEX REPLACE "[ \t\r\n]+" " " text "${text}")
  string(STRIP "${text}" text)
  string(APPEND all "${name}\n${text}\n")
endforeach()
string(SHA256 digest "${all}")
string(SUBSTRING "${digest}" 0 16 digest)
string(REPLACE ";" ", " names "${seen}")
file(CONFIGURE OUTPUT "${OUT}" CONTENT "// Generated at build time from ${names} (idl/tools/wire_types_digest.cmake).
#include \"macsim/dds/wire.h\"

namespace macsim::dds {
std::string_view session_wire_types() { return \"${digest}\"; }
}  // namespace macsim::dds
" @ONLY)
