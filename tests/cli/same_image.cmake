# Renders twice and requires byte-identical PNGs (pr_same_image in cli_tests.cmake).
# Variables: EXE, WORKDIR, A and B (|-separated arguments, each run ending with its own --out:
# a.png and b.png).
file(MAKE_DIRECTORY ${WORKDIR})
foreach(run A B)
    string(REPLACE "|" ";" args "${${run}}")
    execute_process(COMMAND ${EXE} ${args} WORKING_DIRECTORY ${WORKDIR} TIMEOUT 120
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "prismrelief ${args} failed (${rc}): ${err}")
    endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORKDIR}/a.png ${WORKDIR}/b.png
                RESULT_VARIABLE same)
if(NOT same EQUAL 0)
    message(FATAL_ERROR "images differ:\n  ${A}\n  ${B}")
endif()
