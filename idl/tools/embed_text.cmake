# Writes a text file into a C++ source as one character array, at build time:
#   cmake -DIN=file -DOUT=file.cpp -DSYMBOL=ns::kName -P embed_text.cmake
# The array is `extern const char kName[]` in namespace `ns`, the file's bytes as a raw string.
file(READ "${IN}" text)
set(delimiter "macsim_embedded")
string(FIND "${text}" ")${delimiter}\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} holds the raw string's end marker ')${delimiter}\"'")
endif()
string(REGEX MATCH "^(.*)::([^:]+)$" _ "${SYMBOL}")
set(namespace "${CMAKE_MATCH_1}")
set(name "${CMAKE_MATCH_2}")
get_filename_component(source_name "${IN}" NAME)
file(CONFIGURE OUTPUT "${OUT}" CONTENT "// Generated at build time from ${source_name} (idl/tools/embed_text.cmake).
namespace ${namespace} {
extern const char ${name}[];
const char ${name}[] = R\"${delimiter}(${text})${delimiter}\";
}  // namespace ${namespace}
" @ONLY)
