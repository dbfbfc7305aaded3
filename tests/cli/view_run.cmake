# One viewer test under a virtual X server (xvfb-run): runs `prismrelief view` (and `render` for
# the expected images), then checks coverage with view_mask_check. Prints VIEW_TEST_SKIPPED
# (CTest's SKIP_REGULAR_EXPRESSION) when no X server can be started, instead of passing.
# Variables: EXE, CHECK (view_mask_check), WORKDIR, CASE, MESHES, SHADERS, PRELOAD (LD_PRELOAD list
# for the viewer in the sanitizer build, else empty).
file(REMOVE_RECURSE ${WORKDIR})
file(MAKE_DIRECTORY ${WORKDIR})
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
    message("VIEW_TEST_SKIPPED: xvfb-run is not installed (scripts/setup.sh installs xvfb and xauth)")
    return()
endif()

# Under the sanitizer preset, LSAN_OPTIONS names tests/lsan.supp (Mesa's own leaks). The viewer
# also loads the X11/GLX side of the system's GL and GLFW, which keep allocations until exit the
# same way: add those libraries (never our code) to a copy used by the viewer's run only.
if("$ENV{LSAN_OPTIONS}" MATCHES "suppressions=([^:]+)")
    set(supp ${CMAKE_MATCH_1})
    if(EXISTS ${supp})
        file(READ ${supp} supp_text)
        file(WRITE ${WORKDIR}/lsan_view.supp "${supp_text}\n# viewer (tests/cli/view_run.cmake)\n"
             "leak:libGLX_mesa.so\nleak:libGLX.so\nleak:libGLdispatch.so\nleak:libX11.so\n"
             "leak:libxcb\nleak:libglfw.so\n")
        string(REPLACE "suppressions=${supp}" "suppressions=${WORKDIR}/lsan_view.supp" lsan "$ENV{LSAN_OPTIONS}")
        set(ENV{LSAN_OPTIONS} "${lsan}")
    endif()
endif()

# Runs the viewer under xvfb-run; sets view_out and view_err (stdout, stderr) in the caller.
function(run_view)
    set(launch ${EXE})
    if(PRELOAD) # sanitizer build (view_tests.cmake): keep Mesa's GLX/DRI libraries mapped to the end
        set(launch env LD_PRELOAD=${PRELOAD} ${EXE})
    endif()
    execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24" ${launch} view ${ARGN}
                    WORKING_DIRECTORY ${WORKDIR}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 240)
    # (Not xvfb-run's cleanup error after the viewer ran, which turned a failure into a skip:
    # found by a review, thirty-eighth session.)
    string(REPLACE "xvfb-run: error: problem while cleaning up temporary directory" "" start_err "${err}")
    if(start_err MATCHES "xvfb-run: error|Xvfb failed to start|cannot open display")
        message("VIEW_TEST_SKIPPED: no X server could be started under xvfb-run:\n${err}")
        set(view_skipped TRUE PARENT_SCOPE)
        return()
    endif()
    if(view_expect_exit) # set by the caller: the run must fail with this status
        if(NOT rc EQUAL view_expect_exit)
            message(FATAL_ERROR "view ${ARGN}: exit ${rc}, expected ${view_expect_exit}:\n${out}\n${err}")
        endif()
    elseif(NOT rc EQUAL 0)
        message(FATAL_ERROR "view ${ARGN} failed (exit ${rc}):\n${out}\n${err}")
    endif()
    message("${out}")
    set(view_out "${out}" PARENT_SCOPE)
    set(view_err "${err}" PARENT_SCOPE)
endfunction()

function(run_render)
    execute_process(COMMAND ${EXE} render ${ARGN} WORKING_DIRECTORY ${WORKDIR}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 240)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "render ${ARGN} failed (exit ${rc}):\n${err}")
    endif()
endfunction()

function(check)
    execute_process(COMMAND ${CHECK} ${ARGN} WORKING_DIRECTORY ${WORKDIR}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("${out}${err}")
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "check failed: ${ARGN} (images kept in ${WORKDIR})")
    endif()
endfunction()

# Fails with `why` and the text unless `text` matches `regex` (expect_match) or does not
# (expect_no_match).
function(expect_match text regex why)
    if(NOT text MATCHES "${regex}")
        message(FATAL_ERROR "${why}:\n${text}")
    endif()
endfunction()
function(expect_no_match text regex why)
    if(text MATCHES "${regex}")
        message(FATAL_ERROR "${why}:\n${text}")
    endif()
endfunction()

set(torus --mesh ${MESHES}/torus.obj --height builtin:bricks --size 160x120)

if(CASE STREQUAL "single")
    # The viewer's image is render's: same camera, same size, same renderer. Tolerance: a few
    # pixels, should a driver round the blit or the clear differently (here it is exact).
    run_view(${torus} --technique prism --frames 3 --screenshot view.png)
    if(view_skipped)
        return()
    endif()
    run_render(${torus} --technique prism --out render.png)
    check(same view.png render.png 4)
    # Soft shadows with a light size: the viewer draws them as render does (and the size matters
    # here: the images at sizes 8 and 2 differ).
    set(soft --technique relaxed-cone --shadows soft --light 1,0.35,0.2)
    run_view(${torus} ${soft} --light-size 8 --frames 2 --screenshot soft_view.png)
    run_render(${torus} ${soft} --light-size 8 --out soft.png)
    check(equal soft_view.png soft.png 4) # (every channel: `same` compares coverage)
    run_render(${torus} ${soft} --out soft_default.png)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORKDIR}/soft.png ${WORKDIR}/soft_default.png
                    RESULT_VARIABLE soft_same)
    if(soft_same EQUAL 0)
        message(FATAL_ERROR "--light-size 8 drew the default light's image")
    endif()
    # A lower render scale is scaled up without blending: alpha stays coverage.
    run_view(${torus} --technique pom --render-scale 0.5 --frames 2 --screenshot half.png)
    check(binary half.png)
    # One frame is the counting frame, not timed: "n/a", not 0.00 ms.
    run_view(${torus} --technique pom --frames 1)
    expect_match("${view_out}" "pom draw n/a \\([0-9.]+ samples/fragment\\); frame n/a" "one frame printed a time")
elseif(CASE STREQUAL "split")
    # POM | prism: each half is that technique's render, and the prism half covers pixels outside
    # the base outline that POM's does not (true silhouettes).
    run_view(${torus} --split pom,prism --divider 0.5 --frames 3 --screenshot split.png)
    if(view_skipped)
        return()
    endif()
    # The walk's half says how many prisms its rays cross, as bench's ppf_mean; pom's does not.
    expect_match("${view_out}"
                 "pom draw [0-9.]+ ms median of [0-9]+ draws? \\([0-9.]+ samples/fragment\\); prism:relief draw [0-9.]+ ms median of [0-9]+ draws? \\([0-9.]+ samples/fragment, [1-9][0-9.]* prisms/fragment\\)"
                 "the summary does not give the walk's prisms per fragment")
    run_render(${torus} --technique pom --out pom.png)
    run_render(${torus} --technique prism --out prism.png)
    check(split split.png pom.png prism.png 0.5 4 20)
    # The prism's exit and shell per half, named as --techniques lists name them: each half is
    # render's image with the same options.
    run_view(${torus} --split prism:relief:exact,prism:relief:walk:full --divider 0.5 --frames 2
             --screenshot exits.png)
    expect_match("${view_out}" "prism:relief:exact draw .*prism:relief:walk:full draw"
                 "the halves are not named prism:relief:exact and prism:relief:walk:full")
    run_render(${torus} --technique prism --prism-exit exact --out exact.png)
    run_render(${torus} --technique prism --prism-shell full --out full.png)
    check(split exits.png exact.png full.png 0.5 4 0)
    # The reference's shadow map is drawn whole in a split view: the viewer's scissor (the
    # half's columns) kept its clear and draws to those columns, and most of the reference half
    # came out in shadow (found by a review).
    set(lit --shadows hard --light 1,0.35,0.2)
    run_view(${torus} ${lit} --split pom,reference --divider 0.5 --frames 2 --screenshot ref_split.png)
    run_render(${torus} ${lit} --technique pom --out pom_lit.png)
    run_render(${torus} ${lit} --technique reference --out reference_lit.png)
    check(scaled ref_split.png pom_lit.png reference_lit.png 0.5 4) # (every channel, at scale 1)
    # Below render scale 1 both halves are scaled by the whole image's ratio: at 161 columns from
    # 81 each half was stretched by its own (41 to 81, 40 to 80), and the left half was out of
    # line with render's image scaled up in 339 pixels.
    set(small --mesh ${MESHES}/torus.obj --height builtin:bricks)
    run_view(${small} --size 161x97 --split pom,prism --divider 0.5 --render-scale 0.5 --frames 2
             --screenshot scaled.png)
    run_render(${small} --size 81x49 --technique pom --out pom_small.png)
    run_render(${small} --size 81x49 --technique prism --out prism_small.png)
    check(scaled scaled.png pom_small.png prism_small.png 0.5 0)
    # The divider line is drawn on the right half's first column, 81 of 161 (at 0.5 too): it was
    # drawn at 0.5 * 161 = 80.5, on column 80, a column left of where the halves meet.
    foreach(scale 1 0.5)
        run_view(${small} --size 161x97 --split pom,prism --divider 0.5 --render-scale ${scale} --frames 2
                 --no-panel --screenshot-ui --screenshot line_${scale}.png)
        check(divider line_${scale}.png 81)
    endforeach()
elseif(CASE STREQUAL "overlay")
    # The shell's wireframe changes colours, never coverage.
    run_view(${torus} --technique prism --overlay shell --frames 2 --screenshot shell.png)
    if(view_skipped)
        return()
    endif()
    run_view(${torus} --technique prism --frames 2 --screenshot plain.png)
    check(rgb shell.png plain.png 200)
    run_view(${torus} --technique pom --overlay base --reference-overlay --frames 2 --screenshot base.png)
    run_render(${torus} --technique pom --out pom.png)
    check(rgb base.png pom.png 100)
    # The reference overlay over the reference tints nothing, at any render scale: the reference
    # image was scaled up with linear filtering and the view with nearest, so at 0.75 silhouette
    # pixels that do not differ were tinted (26 here).
    foreach(overlay "" --reference-overlay)
        run_view(--scene ${MESHES}/scenes/plane_and_torus.json --size 200x150 --technique reference ${overlay}
                 --render-scale 0.75 --frames 2 --screenshot-ui --no-panel --screenshot reference${overlay}.png)
    endforeach()
    check(equal reference.png reference--reference-overlay.png 0)
elseif(CASE STREQUAL "drop")
    # A dropped mesh replaces the scene (framed anew); a bad file is reported and the viewer goes on.
    run_view(${torus} --technique relief --frames 3 --drop nonexistent.obj --drop ${MESHES}/cube.obj
             --screenshot cube.png)
    if(view_skipped)
        return()
    endif()
    expect_match("${view_err}" "nonexistent.obj" "the bad drop was not reported")
    # Its summary counts the dropped scene (it printed the torus' samples per fragment: samples
    # are counted every tenth frame, and three frames did not reach the next).
    string(REGEX MATCH "[0-9.]+ samples/fragment" dropped_count "${view_out}")
    run_view(--mesh ${MESHES}/cube.obj --height builtin:bricks --size 160x120 --technique relief --frames 3)
    string(REGEX MATCH "[0-9.]+ samples/fragment" cube_count "${view_out}")
    if(NOT dropped_count STREQUAL cube_count)
        message(FATAL_ERROR "after the drop the summary says ${dropped_count}, the cube alone ${cube_count}")
    endif()
    run_render(--mesh ${MESHES}/cube.obj --height builtin:bricks --size 160x120 --technique relief --out cube_render.png)
    check(same cube.png cube_render.png 4)
    # A dropped file's error is its own, not said under the flag that named the map before.
    # A missing image and a folder are said as a missing mesh and a folder are, whatever the name
    # ends in ("nonexistent.png: cannot open: No such file or directory", "adir: cannot load this
    # file type"; an exploratory session, forty-ninth).
    file(MAKE_DIRECTORY ${WORKDIR}/adir)
    run_view(${torus} --technique relief --frames 2 --drop nonexistent.png --drop adir)
    expect_match("${view_err}" "warning: nonexistent.png: does not exist" "the missing dropped image was not said as missing")
    expect_match("${view_err}" "warning: adir: is a folder \\(drop a mesh or a height image\\)" "the dropped folder was not said as one")
    # A refused drop's load warnings are not said before its error (its "no texture coordinates"
    # was; forty-ninth session); a drop taken says its own.
    file(WRITE ${WORKDIR}/huge.obj "v 0 0 0\nv 2e30 0 0\nv 0 2e30 0\nf 1 2 3\n")
    file(WRITE ${WORKDIR}/small.obj "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    run_view(${torus} --technique relief --frames 2 --drop huge.obj --drop small.obj)
    expect_match("${view_err}" "warning: huge.obj: the object is" "the refused drop was not said")
    expect_no_match("${view_err}" "huge.obj: no texture coordinates" "the refused drop's load warning was said")
    expect_match("${view_err}" "small.obj: no texture coordinates" "the taken drop's load warning was not said")
elseif(CASE STREQUAL "shader_error")
    # A broken shader in --shader-dir is reported with file and line. Interactively the viewer
    # shows it in the panel and goes on (hot reload); with --frames a frame that cannot be drawn
    # fails the run: exit 1 and no screenshot (never a blank image).
    file(COPY ${SHADERS}/ DESTINATION ${WORKDIR}/shaders)
    file(READ ${WORKDIR}/shaders/surface.frag text)
    file(WRITE ${WORKDIR}/shaders/surface.frag "${text}\nthis is not glsl;\n")
    set(view_expect_exit 1)
    run_view(${torus} --technique pom --frames 3 --shader-dir ${WORKDIR}/shaders --screenshot broken.png)
    if(view_skipped)
        return()
    endif()
    expect_match("${view_err}" "prismrelief: error: .*shaders/surface.frag:[0-9]+"
                 "the compile error was not reported with file and line")
    if(EXISTS ${WORKDIR}/broken.png)
        message(FATAL_ERROR "a screenshot was written although no frame could be drawn")
    endif()
    # An unwritable screenshot fails the run too.
    run_view(${torus} --technique pom --frames 2 --screenshot ${WORKDIR}/no/such/dir/x.png)
    expect_match("${view_err}" "prismrelief: error: .*x.png" "an unwritable screenshot was not reported")
elseif(CASE STREQUAL "cone_build")
    # Cone maps the viewer lacks (neither built nor cached) are built on a thread while it draws
    # relief; with --frames the last frame waits for them, so the screenshot is render's image.
    set(noise --mesh ${MESHES}/torus.obj --height builtin:noise@128 --size 160x120 --technique relaxed-cone)
    run_view(${noise} --cache-dir view_cache --frames 4 --screenshot built.png)
    if(view_skipped)
        return()
    endif()
    expect_match("${view_out}"
                 "built the relaxed cone map of builtin:noise@128 in [0-9.]+ s \\([1-9][0-9]* frames? drawn with relief meanwhile\\)"
                 "the relaxed cone map was not built on a thread")
    run_render(${noise} --cache-dir render_cache --out render.png)
    check(same built.png render.png 0)
    # The frames drawn with relief meanwhile do not count towards --frames: four frames of the
    # technique follow the build, and the first of them counts samples as a first frame does (the
    # summary timed the technique's first draw alone, its shaders' compile, and counted nothing).
    string(REGEX MATCH "view: 4 frames at 160x120: relaxed-cone draw [0-9.]+ ms median of [0-9]+ draws? \\(([0-9.]+) samples/fragment\\)"
           built_summary "${view_out}")
    if(NOT built_summary)
        message(FATAL_ERROR "after the build the summary is not four frames of relaxed-cone with samples:\n${view_out}")
    endif()
    set(built_samples ${CMAKE_MATCH_1})
    # The next run finds both maps in the cache: nothing is built, the first frame is the technique.
    run_view(${noise} --cache-dir view_cache --frames 1 --screenshot cached.png)
    expect_no_match("${view_out}" "built the" "the cached maps were built again")
    check(same cached.png render.png 0)
    expect_match("${view_out}" "relaxed-cone draw n/a \\(${built_samples} samples/fragment\\)"
                 "the samples per fragment after the build (${built_samples}) are not the cached run's")
    # A damaged entry is rebuilt on the thread while relief is drawn: the draw rebuilt it, and the
    # window stopped for the build's time.
    file(GLOB entry ${WORKDIR}/view_cache/cone/relaxed-*128x128*)
    list(LENGTH entry entries)
    if(NOT entries EQUAL 1)
        message(FATAL_ERROR "not one relaxed cache entry of 128x128: ${entry}")
    endif()
    file(WRITE ${entry} "damaged")
    run_view(${noise} --cache-dir view_cache --frames 1 --screenshot damaged.png)
    expect_match("${view_err}" "cone-map cache entry [^\n]*relaxed-[^\n]*; rebuilding it"
                 "the damaged entry was not reported")
    expect_match("${view_out}"
                 "built the relaxed cone map of builtin:noise@128 in [0-9.]+ s \\([1-9][0-9]* frames? drawn with relief meanwhile\\)"
                 "the damaged entry was not rebuilt on a thread")
    check(same damaged.png render.png 0)
    # The same in split view, the other half reading its relaxed map from the cache: the damaged
    # cone map is built on the thread while both halves draw. The other half's draw read the
    # cache while that build ran and rebuilt the map in the frame: one frame for the whole build
    # (0.7 s here). Frames drawn meanwhile come ten a second with --frames: a build of 0.35 s or
    # more that saw fewer than two stopped the window.
    set(split --mesh ${MESHES}/torus.obj --height builtin:noise@384 --size 160x120 --cache-dir split_cache)
    run_render(${split} --technique relaxed-cone --out split_render.png)
    file(GLOB entry ${WORKDIR}/split_cache/cone/cone-*384x384*)
    file(WRITE ${entry} "damaged")
    run_view(${split} --split cone,relaxed-cone --frames 1)
    if(NOT view_out MATCHES "built the cone map of builtin:noise@384 in ([0-9.]+) s \\(([0-9]+) frames? drawn with relief meanwhile\\)")
        message(FATAL_ERROR "the damaged cone map of a split view was not rebuilt on a thread:\n${view_out}")
    endif()
    set(build_s ${CMAKE_MATCH_1})
    set(meanwhile ${CMAKE_MATCH_2})
    if(build_s GREATER_EQUAL 0.35 AND meanwhile LESS 2)
        message(FATAL_ERROR "the window drew ${meanwhile} frame(s) in the ${build_s} s of the build:\n${view_out}")
    endif()
    # A height image dropped while a build runs cancels it (nothing of the old map is cached) and
    # builds the new one's: the screenshot is render's with the dropped image.
    run_view(--mesh ${MESHES}/torus.obj --height builtin:noise@512 --size 160x120 --technique relaxed-cone
             --cache-dir drop_cache --frames 3 --drop render.png --screenshot dropped.png)
    expect_no_match("${view_out}" "builtin:noise@512"
                    "the build for the replaced height map was not cancelled")
    expect_match("${view_out}" "built the relaxed cone map of [^ ]*render.png"
                 "the dropped height map's cone maps were not built on a thread")
    file(GLOB stale ${WORKDIR}/drop_cache/cone/*512x512*)
    if(stale)
        message(FATAL_ERROR "a cancelled build left cache entries: ${stale}")
    endif()
    run_render(--mesh ${MESHES}/torus.obj --height render.png --size 160x120 --technique relaxed-cone
               --cache-dir render_cache --out dropped_render.png)
    check(same dropped.png dropped_render.png 0)
    # --cone-backend gpu: the compute shader needs the viewer's context, so the draw builds them.
    run_view(${noise} --cache-dir gpu_cache --cone-backend gpu --frames 2 --screenshot gpu.png)
    expect_no_match("${view_out}" "built the" "with --cone-backend gpu the maps were built on a thread")
    check(same gpu.png render.png 0)
else()
    message(FATAL_ERROR "unknown CASE ${CASE}")
endif()
