# The digest a session names its wire types by (idl/tools/wire_types_digest.cmake): the same
# for the same types whatever their comments and blank space, another when a field of a
# recorded type changes or a file the recorded types include changes, and the same when an IDL
# file they do not include changes.
#   cmake -DSOURCE=<repository> -DWORK=<scratch folder> -P wire_types_digest_test.cmake
cmake_minimum_required(VERSION 3.16)
set(script ${SOURCE}/idl/tools/wire_types_digest.cmake)
file(REMOVE_RECURSE ${WORK})
file(COPY ${SOURCE}/idl/kurt ${SOURCE}/idl/ros2 DESTINATION ${WORK} FILES_MATCHING PATTERN "*.idl")

function(digest out)
  execute_process(
    COMMAND ${CMAKE_COMMAND} "-DROOTS=${WORK}/kurt/macsim_msgs.idl;${WORK}/ros2/simulation_interfaces.idl"
            "-DSEARCH=${WORK}/kurt;${WORK}/ros2" -DOUT=${WORK}/digest.cpp -P ${script}
    RESULT_VARIABLE code ERROR_VARIABLE error)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "the digest script failed: ${error}")
  endif()
  file(READ ${WORK}/digest.cpp text)
  if(NOT text MATCHES "return \"([0-9a-f]+)\";")
    message(FATAL_ERROR "no digest in ${WORK}/digest.cpp:\n${text}")
  endif()
  string(LENGTH "${CMAKE_MATCH_1}" length)
  if(NOT length EQUAL 16)
    message(FATAL_ERROR "the digest ${CMAKE_MATCH_1} is not 16 hex digits")
  endif()
  set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

function(expect what a b equal)
  if(equal AND NOT a STREQUAL b)
    message(FATAL_ERROR "${what}: the digest changed, ${a} to ${b}")
  elseif(NOT equal AND a STREQUAL b)
    message(FATAL_ERROR "${what}: the digest stayed ${a}")
  endif()
  message(STATUS "${what}: ${a} ${b} as expected")
endfunction()

# Replaces every FROM in FILE by TO, failing when FILE has none.
function(edit file from to)
  file(READ ${file} text)
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${file} has no '${from}' to change")
  endif()
  string(REPLACE "${from}" "${to}" text "${text}")
  file(WRITE ${file} "${text}")
endfunction()

digest(original)
edit(${WORK}/ros2/std_msgs.idl "module" "// a comment\n/* a block\n   comment */\n\n  module")
digest(commented)
expect("comments and blank space" ${original} ${commented} TRUE)
edit(${WORK}/kurt/plan_msgs.idl "module" "struct NotRecorded { long a; };\nmodule")
digest(unrecorded)
expect("a type sessions do not record" ${original} ${unrecorded} TRUE)
edit(${WORK}/kurt/macsim_msgs.idl "uint64 steps_asked;" "uint32 steps_asked;")
digest(field)
expect("a field of a recorded reply" ${original} ${field} FALSE)
file(COPY ${SOURCE}/idl/kurt/macsim_msgs.idl DESTINATION ${WORK}/kurt)
edit(${WORK}/ros2/builtin_interfaces.idl "int32 sec" "int64 sec")
digest(included)
expect("a type a recorded one includes" ${original} ${included} FALSE)
