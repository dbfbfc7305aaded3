# Renders the same scene with two backends and requires byte-identical PNGs.
# Variables: EXE, WORKDIR, MESH.
file(MAKE_DIRECTORY ${WORKDIR})
foreach(backend osmesa egl)
    execute_process(COMMAND ${EXE} render --mesh ${MESH} --height builtin:noise --technique relief
                            --size 96x64 --backend ${backend} --out ${WORKDIR}/${backend}.png
                    RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 120)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "--backend ${backend} failed (${rc}): ${err}")
    endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORKDIR}/osmesa.png ${WORKDIR}/egl.png
                RESULT_VARIABLE same)
if(NOT same EQUAL 0)
    message(FATAL_ERROR "EGL and OSMesa images differ")
endif()
