# Copies each file of the folder FROM into the folder TO when TO lacks it or holds other text,
# and leaves the others, with their times, as they are (run with cmake -P at build time: what
# includes a generated file recompiles only when its text changed).
file(GLOB files LIST_DIRECTORIES false "${FROM}/*")
if(files)
  execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${files} ${TO}
                  RESULT_VARIABLE failed)
  if(failed)
    message(FATAL_ERROR "cannot copy the generated files of ${FROM} into ${TO}")
  endif()
endif()
