# sinter run --restart with a scene file edited since the run (docs/getting-started.md): the
# scene's explicit dt and [output] interval win over the checkpoint's, and the restart warns of
# each on stderr without --log. mech.scene (samples every 0.002 s) is stopped at 0.02 s; the copy
# then asks dt = 5e-6 s (was 1e-5 s) and a sample every 0.004 s, so the restarted run's samples
# are 0.024, 0.028, ..., 0.04 s: 11 rows before the stop and 5 after. (Before the fix the restart
# said nothing, kept dt = 1e-5 s and sampled at 0.022 s first.) Invoked by ctest:
#   cmake -DSINTER=<sinter executable> -DSCENE=<mech.scene> -DOUT=<directory> -P cli_restart_edited.cmake
file(REMOVE_RECURSE ${OUT})
get_filename_component(dir ${SCENE} DIRECTORY)
file(MAKE_DIRECTORY ${OUT})
file(COPY ${SCENE} ${dir}/mech_n10.xyz DESTINATION ${OUT})
execute_process(COMMAND ${SINTER} run ${OUT}/mech.scene -o ${OUT}/run --end-time 0.04
                        --stop-at 0.02 --progress 0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the run to 0.02 s failed (${rc}): ${out}${err}")
endif()
file(READ ${OUT}/mech.scene text)
string(REPLACE "dt = 1e-5" "dt = 5e-6" text "${text}")
string(REPLACE "interval = 0.002" "interval = 0.004" text "${text}")
file(WRITE ${OUT}/mech.scene "${text}")
execute_process(COMMAND ${SINTER} run ${OUT}/mech.scene -o ${OUT}/run --end-time 0.04
                        --restart ${OUT}/run/checkpoint.bin --progress 0
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the restart failed (${rc}): ${out}${err}")
endif()
foreach(expect "the scene's time step dt = 5.0000000000000004e-06 s replaces the checkpoint's 1.0000000000000001e-05 s"
               "the scene's \\[output\\] interval = 0.0040000000000000001 s replaces the run's 0.002 s")
  if(NOT err MATCHES "sinter \\[warning\\]: restart: ${expect}")
    message(FATAL_ERROR "no warning '${expect}' on stderr")
  endif()
endforeach()
file(STRINGS ${OUT}/run/series.csv rows REGEX "^[0-9]")
list(LENGTH rows count)
list(GET rows 11 first_after)
list(GET rows -1 last)
if(NOT count EQUAL 16 OR NOT first_after MATCHES "^0\\.0240*[0-9]?[0-9]?," OR NOT last MATCHES "^0\\.04")
  message(FATAL_ERROR "expected 11 + 5 samples, the first after the restart at 0.024 s and the "
                      "last at 0.04 s; got ${count}, '${first_after}' ... '${last}'")
endif()
