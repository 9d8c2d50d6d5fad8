# sinter run --threads: a scene run on one thread and on two writes the same series, bit for bit
# (the library's results do not depend on the thread count). Invoked by ctest:
#   cmake -DSINTER=<sinter executable> -DSCENE=<scene> -DOUT=<directory> -P cli_threads.cmake
foreach(threads 1 2)
  execute_process(COMMAND ${SINTER} run ${SCENE} -o ${OUT}/threads${threads} --threads ${threads}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "sinter run --threads ${threads} failed (${rc}): ${out}${err}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/threads1/series.csv
                        ${OUT}/threads2/series.csv RESULT_VARIABLE differ)
if(NOT differ EQUAL 0)
  message(FATAL_ERROR "series.csv differs between --threads 1 and --threads 2")
endif()
