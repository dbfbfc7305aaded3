# prismrelief conemap: success paths, the cache, one-line errors with nothing written.
# (Included by tests/CMakeLists.txt after cli_tests.cmake, which defines pr_cli, E and BAD.)
set(CM "^prismrelief: error: ")
pr_cli(conemap_cone EXIT 0 EXPECT_FILE c.png STDOUT "c.png: 64x64 cone rg16, built \\(cpu.*ratio min [0-9.]+ mean.*\nwrote c.json"
       JSON c.json CHECKS "width:EQUAL:64|kind:STREQUAL:cone|format:STREQUAL:rg16|from_cache:STREQUAL:OFF|ratio_min:GREATER:0|ratio_max:LESS_EQUAL:1|cache_entry:TYPE:NULL|search_ms:TYPE:NULL|search_cpu_ms:TYPE:NULL|searches_resumed:TYPE:NULL|texels_restarted:TYPE:NULL|seed_ms:TYPE:NULL|seeds:TYPE:NULL"
       ARGS conemap --height builtin:bumps@64 --out c.png --no-cache --json c.json)
pr_cli(conemap_relaxed_rg8 EXIT 0 EXPECT_FILE r.png STDOUT "r.png: 48x48 relaxed rg8"
       ARGS conemap --height builtin:boxes@48 --kind relaxed --format rg8 --threads 1 --out r.png --cache-dir cache)
# --json's ratios are G over the format's steps, as the PNG stores them (81/255 here), not the
# floats they round down to (0.31764704, found by an exploratory session, forty-sixth).
pr_cli(conemap_json_ratios_are_the_stored_steps EXIT 0 EXPECT_FILE n.png
       JSON n.json CHECKS "ratio_min:MATCHES:^0[.]31764705882352|ratio_max:EQUAL:1|ratio_mean:MATCHES:^0[.]54759306"
       ARGS conemap --height builtin:noise@37 --format rg8 --out n.png --no-cache --json n.json)
# A map of one long row is shared among the threads (it took one thread, a row each; found by an
# exploratory session, forty-sixth).
pr_cli(conemap_one_row_takes_the_threads EXIT 0 EXPECT_FILE l.png STDOUT "l.png: 2048x1 relaxed rg16, built \\(cpu, 2 threads\\)"
       ARGS conemap --height builtin:noise@2048x1 --kind relaxed --threads 2 --out l.png --no-cache)
# (OSMesa draws with llvmpipe, where the CPU's threads find the seeds: docs/cone-maps.md, "GPU".)
pr_cli(conemap_gpu EXIT 0 EXPECT_FILE g.png STDOUT "g.png: 48x48 cone rg16, built \\(gpu"
       JSON g.json CHECKS "backend:STREQUAL:gpu|search_ms:GREATER:0|ms:GREATER:0|search_cpu_ms:GREATER_EQUAL:0|searches_resumed:EQUAL:0|texels_restarted:EQUAL:0|seeds:STREQUAL:cpu|seed_ms:GREATER:0"
       ARGS conemap --height builtin:noise@48 --backend gpu --out g.png --no-cache --json g.json)
# The cache: the first run of each pair builds (fresh work folder), the second reads it.
pr_cli(conemap_cache_miss EXIT 0 EXPECT_FILE m.png STDOUT "m.png: 40x40 cone rg16, built"
       ARGS conemap --height builtin:pyramids@40 --out m.png --cache-dir ${PR_CLI_WORK}/conemap_cache/c)
pr_cli(conemap_cache_hit EXIT 0 EXPECT_FILE m.png STDOUT "m.png: 40x40 cone rg16, from the cache"
       JSON m.json CHECKS "from_cache:STREQUAL:ON|cache_entry:TYPE:STRING"
       ARGS conemap --height builtin:pyramids@40 --out m.png --cache-dir ${PR_CLI_WORK}/conemap_cache/c --json m.json)
set_tests_properties(cli.conemap_cache_hit PROPERTIES DEPENDS cli.conemap_cache_miss)
# --json's cache_entry names the entry written, absolute (a relative --cache-dir gave a path that
# meant nothing from another folder), and is null where the cache could not be written (it named
# a file that was never written; found by an exploratory session, thirty-second).
pr_cli(conemap_cache_entry_is_absolute EXIT 0 EXPECT_FILE o.png SETUP "mkdir rel"
       JSON j.json CHECKS "from_cache:STREQUAL:OFF|cache_entry:MATCHES:^/.+/rel/cone/cone-rg16-16x16-[0-9a-f]+[.]bin$"
       ARGS conemap --height builtin:bumps@16 --out o.png --cache-dir rel --json j.json)
# ... without "." parts (--cache-dir ./rel2/ gave ".../cli_work/NAME/./rel2/cone/..."; found by an
# exploratory session, forty-sixth).
pr_cli(conemap_cache_entry_has_no_dot_parts EXIT 0 EXPECT_FILE o.png
       JSON j.json CHECKS "cache_entry:MATCHES:^(/[.]?[^/.][^/]*)+/rel2/cone/cone-rg16-16x16-[0-9a-f]+[.]bin$"
       ARGS conemap --height builtin:bumps@16 --out o.png --cache-dir ./rel2/ --json j.json)
pr_cli(conemap_cache_not_written_has_no_entry EXIT 0 ONE_LINE EXPECT_FILE o.png SETUP "printf x > cfile"
       STDERR "^prismrelief: warning: cone-map cache not written: "
       JSON j.json CHECKS "from_cache:STREQUAL:OFF|cache_entry:TYPE:NULL"
       ARGS conemap --height builtin:bumps@16 --out o.png --cache-dir cfile --json j.json)
# A cache folder that is a loop of links: one warning, naming the folder (every entry was first
# said to be "a symbolic link that loops"), and /proc's "takes no new folder" (it read "No such
# file or directory" as if /proc were missing); found by an exploratory session, fiftieth.
pr_cli(conemap_cache_dir_loop EXIT 0 ONE_LINE EXPECT_FILE o.png SETUP "ln -s l2 l1 && ln -s l1 l2"
       STDERR "^prismrelief: warning: cone-map cache not written: l1/cone: cannot create it: l1 is a symbolic link to l2, which leads back to itself \\(a loop of links\\)"
       ARGS conemap --height builtin:bumps@16 --out o.png --cache-dir l1)
pr_cli(conemap_cache_dir_in_proc EXIT 0 ONE_LINE EXPECT_FILE o.png SETUP "test -d /proc/self || exit 77"
       STDERR "^prismrelief: warning: cone-map cache not written: /proc/self/cone: cannot create it: /proc/self takes no new folder \\(a file system such as /proc or /sys\\)"
       ARGS conemap --height builtin:bumps@16 --out o.png --cache-dir /proc/self)
add_test(NAME cli.conemap_cache_reset COMMAND ${CMAKE_COMMAND} -E rm -rf ${PR_CLI_WORK}/conemap_cache/c)
set_tests_properties(cli.conemap_cache_reset PROPERTIES LABELS "cli" FIXTURES_SETUP conemap_cache)
set_tests_properties(cli.conemap_cache_miss PROPERTIES FIXTURES_REQUIRED conemap_cache)
set_tests_properties(cli.conemap_cache_hit PROPERTIES FIXTURES_REQUIRED conemap_cache)
# Errors: exit 1, one line naming the file or option, no output file.
pr_cli(conemap_bad_height EXIT 1 ONE_LINE STDERR "${CM}.*not_an_image.png: " NO_FILE o.png
       ARGS conemap --height ${BAD}/not_an_image.png --out o.png --no-cache)
pr_cli(conemap_missing_height EXIT 1 ONE_LINE STDERR "${CM}--height: nope.png: " NO_FILE o.png
       ARGS conemap --height nope.png --out o.png --no-cache)
pr_cli(conemap_bad_kind EXIT 1 ONE_LINE STDERR "${CM}--kind: unknown cone-map kind 'wide'" NO_FILE o.png
       ARGS conemap --height builtin:bumps@16 --kind wide --out o.png --no-cache)
pr_cli(conemap_bad_format EXIT 1 ONE_LINE STDERR "${CM}--format: " NO_FILE o.png
       ARGS conemap --height builtin:bumps@16 --format rg32 --out o.png --no-cache)
pr_cli(conemap_bad_backend EXIT 1 ONE_LINE STDERR "${CM}--backend: " NO_FILE o.png
       ARGS conemap --height builtin:bumps@16 --backend tpu --out o.png --no-cache)
# --gl-backend without --backend gpu changed nothing and was ignored.
pr_cli(conemap_gl_backend_without_gpu EXIT 1 ONE_LINE STDERR "${CM}--gl-backend: applies with --backend gpu only" NO_FILE o.png
       ARGS conemap --height builtin:bumps@16 --gl-backend egl --out o.png --no-cache)
pr_cli(conemap_bad_threads EXIT 1 ONE_LINE STDERR "${CM}--threads: " NO_FILE o.png
       ARGS conemap --height builtin:bumps@16 --threads -3 --out o.png --no-cache)
pr_cli(conemap_out_folder_missing EXIT 1 ONE_LINE STDERR "${CM}no/dir/o.png: "
       ARGS conemap --height builtin:bumps@16 --out no/dir/o.png --no-cache)
pr_cli(conemap_needs_out EXIT 2 STDERR "usage: .*--out" ARGS conemap --height builtin:bumps@16)
# --max-image-size holds for a built-in map's default size (512) as for @N; the message says it
# is the default size, not a size after '@' the user never wrote.
pr_cli(max_image_size_builtin_default EXIT 1 ONE_LINE
       STDERR "${CM}--height: builtin:bumps: its default size, 512x512, is over the limit of 16 per side \\(--max-image-size\\): give a size, e.g. builtin:bumps@16" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --height builtin:bumps --technique cone --max-image-size 16 --size 32x32
            --cache-dir mis_cache --out o.png)
# Under 3 per side no pattern shows: it suggested builtin:bumps@1, which is then refused as too
# small (found by an exploratory session, thirtieth). A constant map takes any size.
pr_cli(max_image_size_below_any_pattern EXIT 1 ONE_LINE
       STDERR "${CM}builtin:bumps: its default size, 512x512, is over the limit of 2 per side \\(--max-image-size\\), and its pattern needs at least 3 texels per side: raise the limit" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --color builtin:checker@2 --max-image-size 2 --size 32x32 --out o.png)
pr_cli(max_image_size_below_any_pattern_constant EXIT 1 ONE_LINE
       STDERR "${CM}--height: builtin:const:0.5: its default size, 512x512, is over the limit of 2 per side \\(--max-image-size\\): give a size, e.g. builtin:const:0.5@2" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --height builtin:const:0.5 --max-image-size 2 --size 32x32 --out o.png)
pr_cli(conemap_builtin_too_small EXIT 1 ONE_LINE STDERR "${CM}--height: builtin:bumps@2: too small for its pattern; at least 3"
       NO_FILE o.png ARGS conemap --height builtin:bumps@2 --out o.png --no-cache)
pr_cli(conemap_help EXIT 0 STDOUT "--kind.*--format.*--backend" ARGS conemap --help)
# Both outputs or neither: a report that cannot be written (/proc takes no new files) takes the PNG.
pr_cli(conemap_json_unwritable EXIT 1 ONE_LINE STDERR "${CM}/proc/x.json: " NO_FILE c.png
       ARGS conemap --height builtin:bumps@16 --out c.png --json /proc/x.json --no-cache)

# The fast marchers and self-shadowing from the command line (cone maps built on first use in a
# fresh --cache-dir), and one-line errors for unknown names.
pr_cli(render_relaxed_cone_shadows EXIT 0 EXPECT_FILE s.png STDOUT "s.png: 64x48 relaxed-cone"
       ARGS render --mesh ${M}/plane.obj --height builtin:boxes@64 --technique relaxed-cone --shadows soft
            --size 64x48 --cache-dir rc_cache --out s.png)
pr_cli(compare_fast_marchers EXIT 0 STDOUT "prism:cone .*prism:relaxed-cone .*prism:max-mip"
       JSON f.json CHECKS "results.0.iou:GREATER:0.9|results.1.iou:GREATER:0.9|results.2.iou:GREATER:0.9"
       ARGS compare --mesh ${M}/torus.obj --height builtin:bumps@128 --size 96x96 --cache-dir fm_cache
            --techniques prism:cone,prism:relaxed-cone,prism:max-mip --shadows hard --json f.json)
# Where a neighbour's texture frame differs from the hit prism's, the light's walk through the
# prisms answers, shadow or light (the march in the hit's texture plane is no guide there): the
# UV sphere's bumps near its pole, where u narrows row by row, lost the tops of their shadows
# (26.4 dB against the reference, now 34.9), the cube's next to its edges (25.3, now 32.3). Found
# by an exploratory session (thirty-ninth).
pr_cli(compare_prism_shadows_near_a_pole EXIT 0 JSON p.json
       CHECKS "results.0.psnr:GREATER:31|results.1.psnr:GREATER:31"
       ARGS compare --mesh ${M}/uv_sphere.obj --height builtin:bumps --depth 0.15 --size 128x128 --eye 0.01,3.5,0.01
            --target 0,1,0 --fovy 25 --light 1,0.3,0.2 --shadows hard --cache-dir pole_cache
            --techniques prism,prism:cone --json p.json)
pr_cli(compare_prism_shadows_by_the_cubes_edges EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:30"
       ARGS compare --mesh ${M}/cube.obj --size 160x120 --shadows hard --elevation 35 --techniques prism --json c.json)
# And the triangles that touch such an edge at a corner, whose shell bends with the welded normal
# there: a sheet folded 30 degrees along a hinge, its UVs unbroken across it, cut its bumps'
# shadows along those triangles' diagonals (27.9 dB; 34.5 now).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/hinge.obj "v -1 0 -1\nv -1 0 0\nv 0 0 0\nv 0 0 -1\nv 0.866025404 0.5 0\nv 0.866025404 0.5 -1\nv -1 0 1\nv 0 0 1\nv 0.866025404 0.5 1
vt 0 1\nvt 0 0.5\nvt 0.5 0.5\nvt 0.5 1\nvt 1 0.5\nvt 1 1\nvt 0 0\nvt 0.5 0\nvt 1 0
f 1/1 2/2 3/3 4/4\nf 4/4 3/3 5/5 6/6\nf 2/2 7/7 8/8 3/3\nf 3/3 8/8 9/9 5/5\n")
pr_cli(compare_prism_shadows_by_a_hinge EXIT 0 JSON h.json CHECKS "results.0.psnr:GREATER:32"
       ARGS compare --mesh ${CMAKE_CURRENT_BINARY_DIR}/hinge.obj --height builtin:bumps --shadows hard --light 1,0.8,0.2
            --depth 0.1 --eye -0.6,1.3,1.4 --target 0.5,0.25,0 --size 192x144 --techniques prism --json h.json)
pr_cli(render_cone_backend_gpu EXIT 0 EXPECT_FILE g.png STDOUT "g.png: 64x48 prism"
       ARGS render --mesh ${M}/torus.obj --height builtin:noise@48 --technique prism --marcher relaxed-cone
            --cone-backend gpu --size 64x48 --cache-dir gpu_cache --out g.png)
# Where nothing drawn reads a cone map it is refused, as the quality flags are (it was accepted and
# ignored); one technique of a list that reads one is enough.
pr_cli(cone_backend_unread EXIT 1 ONE_LINE NO_FILE o.png
       STDERR "${CM}--cone-backend: has no effect: --technique relief reads no cone map \\(cone, relaxed-cone and the prism's cone marchers do\\): leave it out"
       ARGS render --mesh ${M}/cube.obj --technique relief --cone-backend cpu --size 16x16 --out o.png)
# (The marcher given is said: "--technique prism reads no cone map" read as if no prism did; found
# by an exploratory session, fifty-third.)
pr_cli(cone_backend_unread_prism_marcher EXIT 1 ONE_LINE NO_FILE o.png
       STDERR "${CM}--cone-backend: has no effect: --technique prism --marcher max-mip reads no cone map"
       ARGS render --mesh ${M}/cube.obj --technique prism --marcher max-mip --cone-backend cpu --size 16x16 --out o.png)
pr_cli(cone_backend_unread_compare EXIT 1 ONE_LINE NO_FILE o.png STDERR "${CM}--cone-backend: has no effect: --techniques pom,prism:max-mip"
       ARGS compare --mesh ${M}/cube.obj --techniques pom,prism:max-mip --cone-backend cpu --size 16x16 --out o.png)
pr_cli(cone_backend_read_in_a_list EXIT 0 EXPECT_FILE o.png
       ARGS compare --mesh ${M}/cube.obj --height builtin:bumps@16 --techniques pom,prism:cone --cone-backend cpu --no-cache --size 16x16 --out o.png)
pr_cli(cone_backend_unknown EXIT 1 ONE_LINE STDERR "${CM}--cone-backend: unknown cone-map backend 'tpu'" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --cone-backend tpu --out o.png)
pr_cli(shadows_unknown EXIT 1 ONE_LINE STDERR "${CM}--shadows: unknown shadow mode 'dark'" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --shadows dark --out o.png)
pr_cli(marcher_unknown EXIT 1 ONE_LINE STDERR "${CM}--marcher: unknown marcher 'warp'" NO_FILE o.png
       ARGS render --mesh ${M}/cube.obj --technique prism --marcher warp --out o.png)
# --no-cache for the drawing commands (conemap had it alone; render_no_cache_writes_no_entry).
pr_cli(render_no_cache_and_cache_dir EXIT 1 ONE_LINE NO_FILE o.png STDERR "${E}--no-cache: conflicts with --cache-dir"
       ARGS render --mesh ${M}/torus.obj --no-cache --cache-dir c --size 8x8 --out o.png)
pr_cli(conemap_no_cache_and_cache_dir EXIT 1 ONE_LINE NO_FILE c.png STDERR "${E}--no-cache: conflicts with --cache-dir"
       ARGS conemap --height builtin:bumps@8 --no-cache --cache-dir c --out c.png)
