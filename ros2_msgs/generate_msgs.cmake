# Writes the ROS 2 interface packages into OUT (cmake -P, at build time): for each package of
# PACKAGES, its package.xml and CMakeLists.txt from SOURCE/<package>/ and a .msg file per IDL
# struct of that package, as `TOPIC types TYPE --msg` prints it (the project's IDL is the only
# source of truth: no .msg is kept in the repository). Types .msg cannot express (unions) are
# left out; a .msg of a type no longer in the IDL is removed.
foreach(var TOPIC SOURCE OUT PACKAGES)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "generate_msgs.cmake: ${var} is not set")
  endif()
endforeach()
string(REPLACE "," ";" PACKAGES "${PACKAGES}")

execute_process(COMMAND ${TOPIC} types OUTPUT_VARIABLE listing RESULT_VARIABLE failed)
if(failed)
  message(FATAL_ERROR "generate_msgs.cmake: '${TOPIC} types' failed")
endif()
string(REPLACE "\n" ";" types "${listing}")

foreach(package ${PACKAGES})
  set(dir ${OUT}/${package})
  file(MAKE_DIRECTORY ${dir}/msg)
  file(GLOB stale ${dir}/msg/*.msg)  # what the IDL still has is taken off this list below
  foreach(file package.xml CMakeLists.txt)
    file(COPY_FILE ${SOURCE}/${package}/${file} ${dir}/${file} ONLY_IF_DIFFERENT)
  endforeach()
  set(count 0)
  foreach(type ${types})
    if(NOT type MATCHES "^${package}/msg/([A-Za-z0-9]+)$")
      continue()
    endif()
    set(name ${CMAKE_MATCH_1})
    execute_process(COMMAND ${TOPIC} types ${type} --msg OUTPUT_VARIABLE definition
                    ERROR_QUIET RESULT_VARIABLE cannot)
    if(cannot OR definition STREQUAL "")
      continue()  # a union (or a struct of one): .msg cannot say it
    endif()
    # Written only when it changed: a colcon workspace linking these sees no new timestamps.
    set(msg ${dir}/msg/${name}.msg)
    string(CONCAT text "# ${package}/${name}: the IDL type ${package}::msg::dds_::${name}_ "
           "(idl/kurt/${package}.idl), field for field.\n" "${definition}")
    set(old "")
    if(EXISTS ${msg})
      file(READ ${msg} old)
    endif()
    if(NOT old STREQUAL text)
      file(WRITE ${msg} "${text}")
    endif()
    list(REMOVE_ITEM stale ${msg})
    math(EXPR count "${count} + 1")
  endforeach()
  if(stale)
    file(REMOVE ${stale})
  endif()
  if(count EQUAL 0)
    message(FATAL_ERROR "generate_msgs.cmake: no type of package ${package} in '${TOPIC} types'")
  endif()
endforeach()
