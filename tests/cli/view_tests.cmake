# prismrelief view (issue #6). Window tests run under xvfb-run and are reported as skipped (not
# passed) when no X server can start; they take the "xvfb" lock so two never race for a display.
if(TARGET pr_view)
    add_executable(view_mask_check ${PROJECT_SOURCE_DIR}/tests/view/view_mask_check.cpp)
    target_link_libraries(view_mask_check PRIVATE pr_core)

    pr_cli(view_help EXIT 0 STDOUT "--split.*--divider.*--overlay.*--screenshot.*--frames" ARGS view --help)
    pr_cli(view_bad_split EXIT 1 ONE_LINE STDERR "${E}--split: expected two techniques"
           ARGS view --mesh ${M}/torus.obj --split pom)
    pr_cli(view_bad_split_name EXIT 1 ONE_LINE STDERR "${E}--split: unknown technique 'magic'"
           ARGS view --mesh ${M}/torus.obj --split pom,magic)
    pr_cli(view_bad_overlay EXIT 1 ONE_LINE STDERR "${E}--overlay: " ARGS view --mesh ${M}/torus.obj --overlay all)
    pr_cli(view_bad_divider EXIT 1 ONE_LINE STDERR "${E}--divider: " ARGS view --mesh ${M}/torus.obj --divider 2)
    # The viewer's own numbers are checked as every command's: --frames "" read as 0 (interactive:
    # a batch script never ended), "010" as octal, "0x3" as 3; a huge one was "Could not convert".
    pr_cli(view_frames_empty EXIT 2 STDERR "usage: --frames: expected a whole number, got an empty value"
           ARGS view --mesh ${M}/torus.obj --frames= --screenshot s.png NO_FILE s.png)
    pr_cli(view_frames_hexadecimal EXIT 2 STDERR "usage: --frames: expected a decimal whole number, got '0x3'"
           ARGS view --mesh ${M}/torus.obj --frames 0x3)
    pr_cli(view_frames_huge EXIT 1 ONE_LINE STDERR "${E}--frames: must be between 0 and 1000000"
           ARGS view --mesh ${M}/torus.obj --frames 99999999999)
    pr_cli(view_divider_empty EXIT 2 STDERR "usage: --divider: expected a number, got an empty value"
           ARGS view --mesh ${M}/torus.obj --split pom,prism --divider=)
    pr_cli(view_render_scale_hexadecimal EXIT 2 STDERR "usage: --render-scale: expected a decimal number, got '0x1'"
           ARGS view --mesh ${M}/torus.obj --render-scale 0x1)
    # A dropped file is an input: the screenshot replaced it.
    pr_cli(view_drop_is_an_input EXIT 1 ONE_LINE STDERR "${E}--screenshot: .*h.png is an input \\(--drop\\): it would be overwritten"
           ARGS view --mesh ${M}/torus.obj --drop h.png --screenshot h.png)
    # A shader under --shader-dir is named by that flag (it named PRISMRELIEF_SHADER_DIR, which
    # --shader-dir sets, when the variable was not given).
    pr_cli(view_screenshot_over_shader_dir EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--screenshot: compositor.frag is an input \\(--shader-dir\\): it would be overwritten"
           ARGS view --mesh ${M}/torus.obj --shader-dir . --screenshot compositor.frag --frames 1 NO_FILE compositor.frag)
    pr_cli(view_drop_empty EXIT 1 ONE_LINE STDERR "${E}--drop: empty file name" ARGS view --mesh ${M}/torus.obj --drop=)
    # An empty screenshot name was usage (exit 2), alone of the file options.
    pr_cli(view_screenshot_empty_name EXIT 1 ONE_LINE STDERR "${E}--screenshot: empty file name"
           ARGS view --mesh ${M}/torus.obj --screenshot= --frames 1)
    pr_cli(view_missing_mesh EXIT 1 ONE_LINE STDERR "${E}.*nonexistent.obj: " ARGS view --mesh nonexistent.obj)
    pr_cli(view_no_display EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --frames 1)

    # Sanitizer build: libglvnd unloads Mesa's GLX and DRI libraries before LeakSanitizer runs, so
    # their leaks would show as "<unknown module>" and escape tests/lsan.supp. Preloading them (after
    # the ASan runtime, which must come first) keeps them mapped and their leaks attributable.
    pr_sanitizer_preload(view_preload libGLX_mesa.so.0 swrast_dri.so)
    foreach(case single split overlay drop shader_error cone_build)
        add_test(NAME view.${case}
                 COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:prismrelief> -DCHECK=$<TARGET_FILE:view_mask_check>
                         -DWORKDIR=${CMAKE_CURRENT_BINARY_DIR}/view_work/${case} -DCASE=${case}
                         -DMESHES=${PROJECT_SOURCE_DIR}/meshes -DSHADERS=${PROJECT_SOURCE_DIR}/shaders
                         "-DPRELOAD=${view_preload}"
                         -P ${CMAKE_CURRENT_SOURCE_DIR}/cli/view_run.cmake)
        set_tests_properties(view.${case} PROPERTIES LABELS "view;gl" TIMEOUT 300 RESOURCE_LOCK xvfb
                             SKIP_REGULAR_EXPRESSION "VIEW_TEST_SKIPPED")
    endforeach()

    # Keys and the window manager (tests/cli/view_keys.sh): synthetic X input under xvfb-run,
    # xdotool for the keys and x11_send for the close button and a dropped file. Skipped (never
    # passed) without xvfb-run, xdotool or Xlib's headers; each viewer runs 60 s at most.
    find_package(X11 QUIET)
    set(x11_send "")
    if(X11_FOUND)
        add_executable(view_x11_send ${PROJECT_SOURCE_DIR}/tests/view/x11_send.cpp)
        target_link_libraries(view_x11_send PRIVATE X11::X11)
        set(x11_send $<TARGET_FILE:view_x11_send>)
    endif()
    foreach(case screenshot screenshot_refused shader_break shader_broken_start compositor_break close_key close_wm techniques orbit tap build divider tab summary popup)
        add_test(NAME view.keys.${case}
                 COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/cli/view_keys.sh ${case} $<TARGET_FILE:prismrelief>
                         $<TARGET_FILE:view_mask_check> "${x11_send}" ${CMAKE_CURRENT_BINARY_DIR}/view_work/keys_${case}
                         ${PROJECT_SOURCE_DIR}/meshes "${view_preload}")
        set_tests_properties(view.keys.${case} PROPERTIES LABELS "view;gl" TIMEOUT 150 RESOURCE_LOCK xvfb
                             SKIP_REGULAR_EXPRESSION "VIEW_TEST_SKIPPED")
    endforeach()
else()
    pr_cli(view_not_built EXIT 1 ONE_LINE STDERR "${E}view: this build has no viewer" ARGS view --mesh ${M}/torus.obj)
endif()

# The wireframe overlay itself (Renderer::draw_overlay) needs no window: an OSMesa GL test.
add_executable(view_overlay_test ${PROJECT_SOURCE_DIR}/tests/view/test_overlay.cpp)
target_link_libraries(view_overlay_test PRIVATE pr_app GTest::gtest_main)
target_compile_definitions(view_overlay_test PRIVATE PR_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
gtest_discover_tests(view_overlay_test PROPERTIES LABELS gl DISCOVERY_TIMEOUT 60)
if(TARGET pr_view)
    # The viewer's camera and panel maths (no window, no GL).
    add_executable(view_unit_test ${PROJECT_SOURCE_DIR}/tests/view/test_orbit.cpp)
    target_link_libraries(view_unit_test PRIVATE pr_view GTest::gtest_main)
    gtest_discover_tests(view_unit_test PROPERTIES LABELS unit DISCOVERY_TIMEOUT 60)
    # --screenshot without --frames: interactive, which a batch script waited on without a word;
    # the note comes once the window is open (view.keys.screenshot), not from a run refused before
    # (here: no display), which it told the window stayed open.
    pr_cli(view_screenshot_without_frames_refused_says_no_more EXIT 1 ENV DISPLAY= WAYLAND_DISPLAY=
           STDOUT "^$" ARGS view --mesh ${M}/torus.obj --screenshot s.png)
    # The reference's cap next to its level: refused as render refuses it (the panel sets no level,
    # so the cap could never act; it was taken, found by an exploratory session, fifty-second).
    pr_cli(view_reference_cap_with_level_refused EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--reference-max-triangles: has no effect: it bounds the automatic level only, and --reference-level 24 is given"
           ARGS view --mesh ${M}/torus.obj --reference-level 24 --reference-max-triangles 100 --frames 1)
    # --backend picks render's headless context; the viewer draws with its window's (it was
    # accepted and ignored).
    pr_cli(view_backend_refused EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--backend: has no effect: view draws with its window's OpenGL context"
           ARGS view --mesh ${M}/torus.obj --backend egl --frames 1)
    # Its usage errors name it (it is out of the help's groups, and CLI11 gave its name as empty:
    # ": given 2 times"; found by an exploratory session, fifty-third).
    pr_cli(view_backend_twice_named EXIT 2 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "^prismrelief: usage: --backend: given 2 times; give it once"
           ARGS view --mesh ${M}/torus.obj --backend egl --backend egl --frames 1)
    pr_cli(view_backend_without_value_named EXIT 2 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "^prismrelief: usage: --backend: 1 required TEXT missing"
           ARGS view --mesh ${M}/torus.obj --frames 1 --backend)
    # The prism's flags with a --split of two base techniques: the panel may turn a half to the
    # prism, which takes them (the refusal meant for compare and bench caught --split too). The
    # options are checked before the window opens: with no display, the window is what fails.
    pr_cli(view_split_keeps_prism_flags EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --split pom,relief --marcher cone --frames 1)
    # Otherwise --split is checked as compare's lists are, and as view without it: these ran (the
    # shell dropped, the marcher unused, --technique ignored, an empty --split unsplit).
    pr_cli(view_split_shell_needs_walk EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--prism-shell: only the walk takes a shell \\(the exit is exact\\)"
           ARGS view --mesh ${M}/torus.obj --split pom,prism --prism-exit exact --prism-shell full --frames 1)
    pr_cli(view_technique_shell_needs_walk EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--prism-shell: only the walk takes a shell \\(the exit is vertex\\)"
           ARGS view --mesh ${M}/torus.obj --technique relief --prism-exit vertex --prism-shell full --frames 1)
    pr_cli(view_split_marcher_every_half_names_its_own EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--marcher: 'prism:cone' in --split prism:cone,prism:linear names the marcher cone, --marcher relief: give one"
           ARGS view --mesh ${M}/torus.obj --split prism:cone,prism:linear --marcher relief --frames 1)
    pr_cli(view_split_and_technique EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY=
           STDERR "${E}--technique: has no effect with --split"
           ARGS view --mesh ${M}/torus.obj --technique prism --split pom,relief --frames 1)
    pr_cli(view_split_empty EXIT 1 ONE_LINE ENV DISPLAY= WAYLAND_DISPLAY= STDERR "${E}--split: no technique given"
           ARGS view --mesh ${M}/torus.obj --split= --frames 1)
    # A half that is not a prism takes the marcher for the panel, though the prism half names its own.
    pr_cli(view_split_marcher_for_the_panel EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --split pom,prism:cone --marcher relief --frames 1)
    # A marcher that every half names is redundant, as in compare's lists and render.
    pr_cli(view_split_marcher_agrees_with_both EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --split prism:cone,prism:cone:exact --marcher cone --frames 1)
    # The quality flags, the reference's and --uv-scale that render refuses where nothing drawn
    # reads them are the viewer's settings for the techniques its panel turns to, and for meshes
    # dropped on it: kept (the options are checked, and the mesh read, before the window opens).
    # (The reference's level and its cap apart: together they are refused, view_reference_cap_with_level_refused.)
    pr_cli(view_keeps_quality_flags EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --technique flat --steps 8 --refine 2 --normal-quality gather --depth-write
                --shadows hard --light-size 4 --reference-max-triangles 1000 --uv-scale 4 --frames 1)
    pr_cli(view_keeps_reference_level EXIT 1 ONE_LINE STDERR "${E}view: cannot open a window" ENV DISPLAY= WAYLAND_DISPLAY=
           ARGS view --mesh ${M}/torus.obj --technique flat --reference-level 2 --frames 1)
endif()
