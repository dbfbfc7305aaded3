# Outputs (docs/robustness.md, "Atomic outputs"): a run that fails leaves the files it would have
# written as they were, a user's earlier file included; two outputs of one run, or an output and an
# input, may not be one file; PNG outputs refuse names of other image formats. Included from
# tests/CMakeLists.txt after cli_tests.cmake (pr_cli, ${E}, ${M}).

# The report cannot be written (/proc takes no new files): the grid, staged first, does not replace
# the user's earlier file of that name (it used to be removed with the new grid).
pr_cli(compare_failure_keeps_earlier_grid EXIT 1 ONE_LINE STDERR "${E}/proc/x.json: " KEEP_FILE keep.png
       ARGS compare --mesh ${M}/cube.obj --techniques pom --size 32x32 --out keep.png --json /proc/x.json)
pr_cli(conemap_failure_keeps_earlier_map EXIT 1 ONE_LINE STDERR "${E}/proc/x.json: " KEEP_FILE keep.png
       ARGS conemap --height builtin:bumps@16 --out keep.png --json /proc/x.json --no-cache)
# ... and a PNG that cannot be written keeps the earlier report.
pr_cli(conemap_failure_keeps_earlier_report EXIT 1 ONE_LINE STDERR "${E}/proc/x.png: " KEEP_FILE keep.json
       ARGS conemap --height builtin:bumps@16 --out /proc/x.png --json keep.json --no-cache)

# One file for two outputs, or an output over an input: refused before any work.
pr_cli(compare_out_and_json_same_file EXIT 1 ONE_LINE STDERR "${E}--json: ./same.png is also the --out file" KEEP_FILE same.png
       ARGS compare --mesh ${M}/cube.obj --techniques pom --size 32x32 --out same.png --json ./same.png)
pr_cli(conemap_out_and_json_same_file EXIT 1 ONE_LINE STDERR "${E}--json: .*same.png is also the --out file" KEEP_FILE same.png
       ARGS conemap --height builtin:bumps@16 --out same.png --json ../conemap_out_and_json_same_file/same.png --no-cache)
# ... also where a folder on the way is a link: a new file named through it was not (the JSON was
# written over the picture, exit 0); and a link's `..` is its target's parent: a/../t.png, `a` a
# link to x/y, is x/t.png, another file than t.png (refused as the same).
pr_cli(render_out_and_json_through_a_folder_link EXIT 1 ONE_LINE SETUP "ln -sfn . here && rm -f n.png"
       STDERR "${E}--json: here/n.png is also the --out file" NO_FILE n.png
       ARGS render --mesh ${M}/cube.obj --size 16x16 --out n.png --json here/n.png)
pr_cli(render_out_through_a_link_and_up EXIT 0 SETUP "mkdir -p x/y && ln -sfn x/y a && rm -f t.png x/t.png" EXPECT_FILE x/t.png
       ARGS render --mesh ${M}/cube.obj --size 16x16 --out a/../t.png --json t.png)
pr_cli(render_out_over_height_map EXIT 1 ONE_LINE STDERR "${E}--out: keep.png is an input \\(--height\\): it would be overwritten" KEEP_FILE keep.png
       ARGS render --mesh ${M}/cube.obj --height keep.png --size 32x32 --out keep.png)
pr_cli(bench_json_over_scene EXIT 1 ONE_LINE STDERR "${E}--json: keep.json is an input \\(--scene\\): it would be overwritten" KEEP_FILE keep.json
       ARGS bench --scene keep.json --techniques pom --size 32x32 --frames 1 --json keep.json)

# PNG data under another format's name.
pr_cli(render_out_jpg EXIT 1 ONE_LINE STDERR "${E}o.jpg: only PNG images are written" NO_FILE o.jpg
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out o.jpg)
pr_cli(conemap_out_tga EXIT 1 ONE_LINE STDERR "${E}c.TGA: only PNG images are written" NO_FILE c.TGA
       ARGS conemap --height builtin:bumps@16 --out c.TGA --no-cache)

# A few covered pixels of a large image are not "coverage 0.0%".
pr_cli(render_small_coverage_has_digits EXIT 0 EXPECT_FILE o.png STDOUT "coverage 0\\.0[0-9][0-9][1-9]%"
       ARGS render --mesh ${M}/torus.obj --size 4096x16 --out o.png)
# One pixel of 2047² read "coverage 0.0000%", all but two of 256² "100.0%" (found by an
# exploratory session, thirty-fourth): digits enough to say neither none nor all.
pr_cli(render_one_pixel_coverage_not_zero EXIT 0 EXPECT_FILE o.png STDOUT "coverage 0\\.00002%"
       ARGS render --mesh ${M}/plane.obj --height builtin:const:1 --eye 0,8000,0 --target 0,0,0 --up 0,0,-1
            --technique flat --size 2047x2047 --out o.png)
# And none is "0.0%" (the fix above printed "0.0000%" for none; found by a review).
pr_cli(render_no_pixel_coverage_zero EXIT 0 EXPECT_FILE o.png STDOUT "coverage 0\\.0%"
       ARGS render --mesh ${M}/torus.obj --eye 0,0,-50 --target 0,0,-100 --size 32x32 --out o.png)
pr_cli(render_two_pixels_short_not_full EXIT 0 EXPECT_FILE o.png STDOUT "coverage 99\\.997%"
       ARGS render --mesh ${M}/plane.obj --height builtin:const:1 --eye 0.37815,1.2,0 --target 0.37815,0,0
            --up 0.31,0,-1 --fovy 45.24 --technique flat --size 256x256 --out o.png)

# Reports say which prism they measured: a row labelled "prism" holds --marcher's choice.
# With --shadows hard the reference is drawn with its geometry's own shadows (a shadow map): the
# prism's, marched through the height field, agree with them (PSNR 26.1 here; 25.9 until the relief
# marcher's light march started on the surface, twenty-third session; 26.7 until the
# maps' axes turned smoothly with the light, twenty-second session; 16.8 against the unshadowed
# reference it drew until the twenty-first session).
pr_cli(compare_reference_with_shadows EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:23"
       ARGS compare --mesh ${M}/plane.obj --height builtin:boxes@128 --depth 0.15 --size 128x96 --light 1,0.6,0.3
            --techniques prism --shadows hard --json c.json)
# With --shadows soft the reference is drawn with soft shadows (shadow maps from 16 directions over
# the light's disc, each filtered over its share of it): the prism's, marched along a ray through
# each of the disc's strips, agree with them (30.3 dB here; 28.8 with one ray towards the disc's
# centre, which kept the shadows' sides hard; 23.0 with the disc the techniques took until the
# twenty-second session, its top on the light's direction, and the angle a clearance makes taken
# without the light's elevation).
pr_cli(compare_soft_shadows_against_the_reference EXIT 0 JSON c.json
       CHECKS "results.0.psnr:GREATER:29.5|reference.shadows:STREQUAL:soft|reference.light_size:EQUAL:12"
       ARGS compare --mesh ${M}/plane.obj --height builtin:boxes@128 --depth 0.15 --size 128x96 --light 1,0.6,0.3
            --techniques prism --shadows soft --light-size 12 --json c.json)
# A soft light a hair over the plane's horizon lights the bumps' flanks facing it as one on the
# horizon does (26.3 dB here, against 40.8 at 0: the walk along the light's own ray ran only
# where the disc's centre was under the horizon; found by an exploratory session, fiftieth).
pr_cli(compare_soft_light_just_over_the_horizon EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:38"
       ARGS compare --mesh ${M}/plane.obj --light 1,1e-3,0 --shadows soft --techniques prism --size 96x72 --json c.json)
# The back of the surface is shadowed: an open sheet seen from below under a light from below
# marches the light through the height field turned over (17.9 dB hard, 18.4 soft, when the back
# was never shadowed; now 28.2 and 37.8), and the back of a closed mesh, seen through a tear of
# the rock's UV seams, lies inside its body, in the dark (10 pixels lit: 20.9 dB, then 22.0; 28.9
# since later sessions; since the forty-first lit by the light's walk from under the surface,
# which here meets the body: the same picture).
pr_cli(compare_sheet_from_below_hard_shadows EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:25"
       ARGS compare --mesh ${M}/plane.obj --height builtin:boxes@128 --depth 0.15 --size 128x96 --light 1,-0.6,0.3
            --eye 0.9,-1.2,1.6 --target 0,0,0 --techniques prism --shadows hard --json c.json)
pr_cli(compare_sheet_from_below_soft_shadows EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:30|results.1.psnr:GREATER:30"
       ARGS compare --mesh ${M}/plane.obj --height builtin:boxes@128 --depth 0.15 --size 128x96 --light 1,-0.6,0.3
            --eye 0.9,-1.2,1.6 --target 0,0,0 --techniques prism,prism:relaxed-cone --shadows soft --light-size 8
            --json c.json)
# The back of an open sheet under a light from its front side, seen through the sheet's open edge:
# a 64 x 1 ramp on the plane wraps to a cliff at its edge, whose back faces the light, which comes
# in under the edge. The march through the heights turned over, in the hit's frame, met the
# wrapped copies past the edge and left that back dark (21.4 dB here, 35.9 now; soft the same;
# found by an exploratory session, fiftieth): the light's walk from under the surface decides.
foreach(shadows hard soft)
    pr_cli(compare_sheet_back_through_its_edge_${shadows} EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:33"
           SETUP "LC_ALL=C awk 'BEGIN {\n printf \"P5\\n64 1\\n255\\n\"\n x = 0\n while (x < 64) {\n printf \"%c\", int(x * 255 / 63 + 0.5)\n x++\n }\n }' > r.pgm"
           ARGS compare --mesh ${M}/plane.obj --height r.pgm --depth 0.2 --size 96x72 --azimuth 305 --elevation 10
                --shadows ${shadows} --reference-level 16 --techniques prism --json c.json)
endforeach()
pr_cli(compare_back_through_a_tear_in_shadow EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:21.6"
       ARGS compare --mesh ${M}/rock.obj --height builtin:boxes --size 128x96 --light 1,0.5,0.3 --techniques prism
            --shadows hard --json c.json)
# The prism's hit tolerance is below a quarter of a pixel whatever the depth: a map whose eight
# steps use a sliver of its range (448/65535) under --depth 150, each step 0.15 units, the plane
# seen from 3 units. At 1e-4 of the depth (0.015 units, most of a pixel) a band ran along every
# step's top: 202 outline pixels wrong against a reference of level 64, IoU 0.963 (the same steps
# in the map's full range at depth 1.5: 2); now 30 (found by an exploratory session, forty-first).
pr_cli(compare_prism_hit_tolerance_low_range_map EXIT 0 JSON c.json
       CHECKS "results.0.iou:GREATER:0.99|results.0.silhouette_wrong_px:LESS:60|results.1.iou:GREATER:0.99"
       ARGS compare --mesh ${M}/plane.obj --height ${BAD}/low_range_steps16.png --depth 150 --eye 0,1.5,3 --target 0,0,0
            --size 128x128 --reference-level 64 --techniques prism,prism:relaxed-cone --json c.json)
# The automatic reference counts that map as sharp (a rise of a quarter of the heights the map
# spans, not of the whole range: here its drop where it wraps, 448 to 0, as the full-range
# staircase's 0.68 of the range made that one sharp): level 8, edges of half a texel; it was level
# 4, whose edges cut the steps' corners, and the prism scored IoU 0.981 against it (forty-first
# session).
pr_cli(compare_reference_sharp_steps_of_a_low_range_map EXIT 0 JSON c.json
       CHECKS "reference.level:EQUAL:8|results.0.iou:GREATER:0.99|results.0.silhouette_wrong_px:LESS:60"
       ARGS compare --mesh ${M}/plane.obj --height ${BAD}/low_range_steps16.png --depth 150 --eye 0,1.5,3 --target 0,0,0
            --size 128x128 --techniques prism --json c.json)
# The prism's colour is filtered as the reference's is, at the level its pixel's footprint asks
# for on the displaced surface: read at level 0 it aliased in minified views (24.3 dB on the
# torus, 27.2 on the plane seen from 8 degrees up; now 29.7 and 35.4; twenty-first session).
pr_cli(compare_prism_colour_is_filtered EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:28"
       ARGS compare --mesh ${M}/torus.obj --height builtin:bricks --color builtin:bricks --size 160x120
            --techniques prism --json c.json)
pr_cli(compare_prism_colour_is_filtered_grazing EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:32"
       ARGS compare --mesh ${M}/plane.obj --height builtin:bricks --color builtin:bricks --size 320x240 --elevation 8
            --techniques prism --json c.json)
# On a mesh with creases (the cube's welded corner normals) the footprint lies in the displaced
# surface's own plane, not the shading's: the vertices' averaged tangents lean with the corner
# normals, and the prism's checker came out blurred and, past that plane's horizon, grey (28.1 dB
# at constant height, 29.5 on the bumps; found by an exploratory session, thirty-fourth).
pr_cli(compare_prism_colour_on_creased_mesh EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:45|results.1.psnr:GREATER:45"
       ARGS compare --mesh ${M}/cube.obj --height builtin:const:1 --color builtin:checker --depth 0.05 --size 128x128
            --techniques prism,prism:relief:exact --json c.json)
pr_cli(compare_prism_colour_on_creased_mesh_bumps EXIT 0 JSON c.json CHECKS "results.0.psnr:GREATER:34"
       ARGS compare --mesh ${M}/cube.obj --color builtin:checker --size 128x128 --techniques prism --json c.json)
# The exact and vertex exits' slab seen from under an open sheet shows the surface's back: lit from
# above it is dark, as the reference (it was shaded as the front, lit: 4.9 dB; found by an
# exploratory session, thirty-fifth); lit from below, lit, and shadowed by the heights turned over
# (the light's march started over them all and never shadowed: 16.0 dB; found by a review).
foreach(light_case "above;0,1,0;30" "below;0.3,-0.4,-1;17")
    list(GET light_case 0 side)
    list(GET light_case 1 light)
    list(GET light_case 2 least)
    pr_cli(compare_prism_slab_from_below_lit_from_${side} EXIT 0 JSON c.json
           CHECKS "results.0.psnr:GREATER:${least}|results.1.psnr:GREATER:${least}"
           ARGS compare --mesh ${M}/plane.obj --height builtin:boxes@64 --depth 0.15 --size 64x48 --eye 0.9,-0.9,1.6
                --target 0,0,0 --light ${light} --shadows hard --techniques prism:relief:exact,prism:linear:vertex --json c.json)
endforeach()
# A wide field of view: the reference's edges measured where the picture stretches them (off the
# axis, 1 / cos^2 of the angle), not at the axis (level 1, the prism's IoU 0.945 against it).
pr_cli(compare_reference_fine_at_wide_field EXIT 0 JSON c.json
       CHECKS "reference.level:GREATER:8|results.0.iou:GREATER:0.995"
       ARGS compare --mesh ${M}/torus.obj --size 64x48 --fovy 178.9 --eye 0.5,0.6,0.8 --target 0,0,0
            --techniques prism --json c.json)
# A large triangle's nearest point in view counts, not its corners alone: a two-triangle floor
# 8 units wide seen from 0.4 above it was built at level 362 (its corners 14 times as far as the
# floor at the bottom of the view), and the prism measured 14.2 dB against it; now at the cap, 21.8.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/floor2.obj "v -4 0 4\nv 4 0 4\nv 4 0 -4\nv -4 0 -4\nvt 0 0\nvt 20 0\nvt 20 20\nvt 0 20\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
pr_cli(compare_reference_fine_near_a_large_triangle EXIT 0 JSON c.json
       CHECKS "reference.level:GREATER:1000|results.0.psnr:GREATER:19"
       ARGS compare --mesh ${CMAKE_CURRENT_BINARY_DIR}/floor2.obj --height builtin:bricks --depth 0.05 --eye 0,0.4,0
            --target 1.5,0,1.5 --size 128x96 --techniques prism --json c.json)
# The criteria bounded before they become levels: from inside the shell with a narrow field of
# view the pixel criterion passed 2^31, the conversion gave INT_MIN, and the level fell to the
# cheap one (362 here) without a word; the texel criterion's 512 now (found by a review).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/floor_wide.obj "v -5000 0 5000\nv 5000 0 5000\nv 5000 0 -5000\nv -5000 0 -5000\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
pr_cli(reference_level_bounded_in_a_narrow_view EXIT 0 STDOUT "reference: level 512,"
       ARGS render --mesh ${CMAKE_CURRENT_BINARY_DIR}/floor_wide.obj --depth 0.5 --eye 0,0.2,0 --target 0.05,0,0.02
            --fovy 1 --technique reference --size 64x48 --out r.png)
# The reference's shadow map stretched by a far object in view: compare says so (its metrics
# count the lost shadows against the techniques; found by an exploratory session, thirty-fourth).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/far_torus.json "{\"objects\": [{\"mesh\": \"${M}/torus.obj\", \"depth\": 0.08},
    {\"mesh\": \"${M}/torus.obj\", \"depth\": 2, \"transform\": {\"translate\": [-300, -40, -300], \"scale\": 30}}],
    \"camera\": {\"eye\": [2.2, 2, 3.2], \"target\": [0, 0, 0]}, \"light\": [1, 0.5, 0.2]}")
pr_cli(compare_says_the_shadow_map_is_coarse EXIT 0 JSON c.json CHECKS "results.0.iou:GREATER:0.9"
       STDERR "compare: the reference's shadow map spans everything the image shows, and on [0-9]+ % of what it shows its texels are wider than two pixels"
       ARGS compare --scene ${CMAKE_CURRENT_BINARY_DIR}/far_torus.json --size 128x80 --techniques prism --shadows hard --json c.json)
# Reports say the normal quality and each object's depth and midlevel as drawn (the automatic
# depth, 4 % of the diagonal, was written nowhere; found by an exploratory session, thirty-fourth).
pr_cli(render_json_says_normal_quality_and_depth EXIT 0 EXPECT_FILE o.png JSON o.json
       CHECKS "normal_quality:STREQUAL:central|objects.0.depth:GREATER:0.155|objects.0.depth:LESS:0.156|objects.0.midlevel:EQUAL:0.5|objects.0.height:EXISTS"
       ARGS render --mesh ${M}/torus.obj --normal-quality central --midlevel 0.5 --size 32x32 --out o.png --json o.json)
pr_cli(compare_json_says_normal_quality EXIT 0 JSON c.json
       CHECKS "results.0.normal_quality:ABSENT|results.1.normal_quality:STREQUAL:gather|objects.0.depth:EQUAL:0.25"
       ARGS compare --mesh ${M}/torus.obj --techniques flat,pom --normal-quality gather --depth 0.25 --size 32x32 --json c.json)
# Each row says the shadows it drew: none for flat.
pr_cli(compare_json_names_the_shadows EXIT 0 JSON c.json
       CHECKS "results.0.shadows:STREQUAL:none|results.0.light_size:ABSENT|results.1.shadows:STREQUAL:soft|results.1.light_size:EQUAL:4|reference.shadows:STREQUAL:soft|reference.light_size:EQUAL:4"
       ARGS compare --mesh ${M}/torus.obj --size 32x24 --techniques flat,pom --shadows soft --light-size 4 --json c.json)
pr_cli(bench_json_names_the_shadows EXIT 0 JSON b.json CHECKS "results.0.shadows:STREQUAL:hard|results.0.light_size:ABSENT"
       ARGS bench --mesh ${M}/torus.obj --size 32x24 --techniques reference --shadows hard --frames 1 --warmup 0 --json b.json)
pr_cli(compare_json_names_the_prism_configuration EXIT 0 JSON c.json
       CHECKS "results.0.technique:STREQUAL:prism|results.0.marcher:STREQUAL:max-mip|results.0.prism_exit:STREQUAL:walk|results.0.prism_shell:STREQUAL:tight|results.1.prism_exit:STREQUAL:exact|results.1.prism_shell:STREQUAL:full|camera.up.1:EQUAL:1"
       ARGS compare --mesh ${M}/cube.obj --techniques prism,prism:linear:exact --marcher max-mip --size 32x32 --json c.json)
pr_cli(bench_json_names_the_prism_configuration EXIT 0 JSON b.json
       CHECKS "results.0.marcher:STREQUAL:cone|results.0.prism_shell:STREQUAL:full"
       ARGS bench --mesh ${M}/cube.obj --techniques prism:cone --prism-shell full --size 32x32 --frames 1 --json b.json)

# ---- Special destinations, links, modes, folders, scenes, signals, the cache's place ----
# pr_cli with what these need (run_cli.cmake): SETUP, a shell command that prepares a fresh work
# folder (exit 77: skipped, for what a machine may not allow), AFTER, a shell command that checks
# the folder after the run, AS_NOBODY (the run without root's powers), ENV as a list, TIMEOUT.
set(pr_output_helpers ${CMAKE_CURRENT_BINARY_DIR}/cli/output_helpers)
file(WRITE ${pr_output_helpers}/as_nobody.sh [[
# Runs a command without root's powers: as root through setpriv (as nobody), else as it is.
if [ "$(id -u)" != 0 ]; then exec "$@"; fi
exec setpriv --reuid=65534 --regid=65534 --clear-groups "$@"
]])
function(pr_output_cli name)
    cmake_parse_arguments(T "ONE_LINE;AS_NOBODY" "EXIT;STDERR;NO_FILE;EXPECT_FILE;KEEP_FILE;SETUP;AFTER;TIMEOUT"
                          "ENV;ARGS" ${ARGN})
    string(REPLACE ";" "|" args "${T_ARGS}")
    set(wrapper "")
    if(T_AS_NOBODY)
        set(wrapper "sh|${pr_output_helpers}/as_nobody.sh")
    endif()
    set(cmd ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:prismrelief> "-DARGS=${args}" -DWORKDIR=${PR_CLI_WORK}/${name}
            -DEXPECT_EXIT=${T_EXIT} "-DSTDERR_REGEX=${T_STDERR}" -DNO_FILE=${T_NO_FILE} -DEXPECT_FILE=${T_EXPECT_FILE}
            -DKEEP_FILE=${T_KEEP_FILE} -DONE_LINE=${T_ONE_LINE} "-DSETUP=${T_SETUP}" "-DAFTER=${T_AFTER}"
            "-DWRAPPER=${wrapper}" -DTIMEOUT=${T_TIMEOUT})
    if(T_ENV)
        set(cmd ${CMAKE_COMMAND} -E env ${T_ENV} ${cmd})
    endif()
    add_test(NAME cli.${name} COMMAND ${cmd} -P ${CMAKE_CURRENT_SOURCE_DIR}/cli/run_cli.cmake)
    set_tests_properties(cli.${name} PROPERTIES LABELS "cli" TIMEOUT 180 SKIP_REGULAR_EXPRESSION "SKIPPED: ")
endfunction()

# A destination that is not a regular file (after links) is refused before any work: renaming over
# it made a FIFO or a device node (as root, --out /dev/null: the system's) a regular PNG.
pr_output_cli(render_out_fifo_refused EXIT 1 ONE_LINE
       STDERR "${E}fifo.png: is not a regular file \\(a FIFO\\): refusing to replace it"
       SETUP "mkfifo fifo.png" AFTER "test -p fifo.png"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out fifo.png)
pr_output_cli(render_out_device_refused EXIT 1 ONE_LINE
       STDERR "${E}full: is not a regular file \\(a character device\\): refusing to replace it"
       SETUP "mknod full c 1 7 2>&1 || exit 77" AFTER "test -c full"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out full)
pr_output_cli(conemap_out_link_to_device_refused EXIT 1 ONE_LINE
       STDERR "${E}null.png: links to /dev/null, which is not a regular file \\(a character device\\)"
       SETUP "ln -s /dev/null null.png" AFTER "test -L null.png"
       ARGS conemap --height builtin:bumps@16 --no-cache --out null.png)

# A link is written through: its target gets the image and the link stays a link (it used to be
# replaced by a regular file, the target keeping its old content). A dangling link's target is
# created where its folder exists, as a shell's `>` does (GNU cp refuses; docs/robustness.md).
pr_output_cli(render_out_through_symlink EXIT 0
       SETUP "mkdir real && echo old > real/t.png && ln -s real/t.png link.png"
       AFTER "test -L link.png && head -c 4 real/t.png | grep -q PNG && ! ls -A real | grep -q tmp"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out link.png)
pr_output_cli(render_out_dangling_symlink_creates_target EXIT 0
       SETUP "mkdir real && ln -s real/new.png link.png"
       AFTER "test -L link.png && head -c 4 real/new.png | grep -q PNG"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out link.png)
pr_output_cli(render_out_dangling_symlink_without_folder EXIT 1 ONE_LINE
       STDERR "${E}link.png: links to nowhere/new.png, but folder nowhere does not exist"
       SETUP "ln -s nowhere/new.png link.png" AFTER "test -L link.png"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out link.png)

# Replacing a file keeps its permission bits (it became 0644).
pr_output_cli(render_out_keeps_mode EXIT 0
       SETUP "echo old > o.png && chmod 640 o.png"
       AFTER "stat -c %a o.png | grep -qx 640 && head -c 4 o.png | grep -q PNG"
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out o.png)

# A folder that cannot be written is refused before the work (this map took 11 s to build, then
# failed). Needs a user without root's powers (root may write anywhere but on read-only mounts).
pr_output_cli(conemap_out_read_only_folder_refused_early EXIT 1 ONE_LINE AS_NOBODY TIMEOUT 5
       STDERR "${E}ro/r.png: cannot write in folder ro: Permission denied"
       SETUP "sh ${pr_output_helpers}/as_nobody.sh true 2>&1 || exit 77 && mkdir ro && chmod 555 ro"
       ARGS conemap --height builtin:noise@1024 --kind relaxed --no-cache --out ro/r.png)

# Files a --scene names are inputs too, found relative to the scene file's folder: --out used to
# overwrite them.
file(WRITE ${pr_output_helpers}/height.json "{\"objects\": [{\"mesh\": \"${M}/cube.obj\", \"height\": \"h.png\"}]}\n")
file(WRITE ${pr_output_helpers}/mesh.json "{\"objects\": [{\"mesh\": \"${M}/cube.obj\"}, {\"mesh\": \"../m.obj\"}]}\n")
pr_output_cli(render_out_over_scene_height EXIT 1 ONE_LINE KEEP_FILE h.png
       STDERR "${E}--out: h.png is an input \\(s.json: objects\\[0\\].height\\): it would be overwritten"
       SETUP "cp ${pr_output_helpers}/height.json s.json"
       ARGS render --scene s.json --size 32x32 --out h.png)
pr_output_cli(compare_json_over_scene_mesh EXIT 1 ONE_LINE KEEP_FILE m.obj
       STDERR "${E}--json: m.obj is an input \\(sub/s.json: objects\\[1\\].mesh\\): it would be overwritten"
       SETUP "mkdir sub && cp ${pr_output_helpers}/mesh.json sub/s.json"
       ARGS compare --scene sub/s.json --techniques pom --size 32x32 --json m.obj)

# A scene's mesh whose name begins "builtin:" is a file in the scene's folder too (meshes have no
# built-ins; it was looked for in the working folder; found by an exploratory session, fifty-third).
file(WRITE ${pr_output_helpers}/builtin_mesh.json "{\"objects\": [{\"mesh\": \"builtin:c.obj\"}]}\n")
pr_output_cli(scene_mesh_named_builtin_in_its_folder EXIT 0 EXPECT_FILE o.png STDOUT "o.png: 16x16 flat"
       SETUP "mkdir sub && cp ${M}/cube.obj sub/builtin:c.obj && cp ${pr_output_helpers}/builtin_mesh.json sub/s.json"
       ARGS render --scene sub/s.json --technique flat --size 16x16 --out o.png)

# compare --tiles: each image alone, as render writes it (byte for byte), named as listed with ':'
# as '_'; tiles are outputs like the others (not over an input, the folder must exist).
set(pr_tile_scene --mesh ${M}/torus.obj --height builtin:bumps@64 --size 48x40)
string(REPLACE ";" " " pr_tile_scene_words "${pr_tile_scene}")
pr_output_cli(compare_tiles_are_renders EXIT 0 SETUP "mkdir t"
       AFTER "R='$<TARGET_FILE:prismrelief> render ${pr_tile_scene_words} --out r.png' && test $(ls t | wc -l) = 3 && $R --technique reference && cmp r.png t/reference.png && $R --technique pom && cmp r.png t/pom.png && $R --technique prism --marcher cone --prism-exit exact && cmp r.png t/prism_cone_exact.png"
       ARGS compare ${pr_tile_scene} --techniques pom,prism:cone:exact,reference --tiles t)
pr_output_cli(compare_tiles_folder_missing EXIT 1 ONE_LINE NO_FILE g.png STDERR "${E}--tiles: t does not exist"
       ARGS compare ${pr_tile_scene} --techniques pom --tiles t --out g.png)
pr_output_cli(compare_tiles_over_an_input EXIT 1 ONE_LINE KEEP_FILE t/pom.png
       STDERR "${E}--tiles: t/pom.png is an input \\(--height\\): it would be overwritten"
       SETUP "mkdir t && $<TARGET_FILE:prismrelief> conemap --height builtin:bumps@16 --no-cache --out t/pom.png"
       ARGS compare --mesh ${M}/torus.obj --height t/pom.png --size 32x32 --techniques pom --tiles t)

# Without an absolute XDG_CACHE_HOME or HOME there is no cache (there was a shared one in /tmp):
# maps are built, with one warning that says how to keep them. TMPDIR plays no part (TMPDIR=/nonexistent
# failed with "filesystem error: temp_directory_path: No such file or directory").
pr_output_cli(render_cone_without_a_cache_location EXIT 0 ONE_LINE EXPECT_FILE o.png
       STDERR "^prismrelief: warning: no cone-map cache: .*maps are built each time \\(--cache-dir DIR"
       ENV --unset=HOME --unset=XDG_CACHE_HOME TMPDIR=/nonexistent
       ARGS render --mesh ${M}/cube.obj --technique relaxed-cone --size 32x32 --out o.png)

# SIGTERM or SIGHUP while a file is staged (strace holds every fsync for 4 s) removes the
# temporary, in the output's folder and in the cache's, and the process still dies of the signal.
# Skipped where strace may not trace. (Not SIGINT: a shell starts background jobs ignoring it.)
file(WRITE ${pr_output_helpers}/signal_cleanup.sh [[
# usage: signal_cleanup.sh EXE WORKDIR SIGNAL STATUS FOLDER ARGS... (STATUS: 128 + the signal's number)
exe=$1 work=$2 sig=$3 expected=$4 folder=$5
shift 5
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
strace -f -qq -o /dev/null true 2>/dev/null || { echo "SKIPPED: strace cannot trace here"; exit 77; }
strace -f -qq -o /dev/null -e trace=fsync -e inject=fsync:delay_enter=4000000 \
    sh -c 'echo $$ > pid && exec "$0" "$@"' "$exe" "$@" &
tracer=$!
tries=0
until ls -A "$folder" 2>/dev/null | grep -q '^\..*\.tmp[0-9]*$'; do
    tries=$((tries + 1))
    if [ $tries -gt 600 ]; then echo "no temporary appeared in $folder"; kill "$(cat pid)"; exit 1; fi
    sleep 0.1
done
echo "staged: $(ls -A "$folder" | grep '\.tmp')"
kill -s "$sig" "$(cat pid)"
wait $tracer
status=$?
left=$(ls -A "$folder" | grep '\.tmp')
if [ "$status" != "$expected" ]; then echo "exit status $status, expected $expected (SIG$sig)"; exit 1; fi
if [ -n "$left" ]; then echo "temporary left behind: $left"; exit 1; fi
echo "died of SIG$sig, no temporary left"
]])
# A signal while two outputs are committed together (strace holds the first rename for 4 s): it
# waits until both are renamed, then the process dies of it; both outputs are the new ones, never
# one new and one old (commit_together). Checked by hand before the fifteenth session.
file(WRITE ${pr_output_helpers}/commit_deferral.sh [[
# usage: commit_deferral.sh EXE WORKDIR
exe=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
strace -f -qq -o /dev/null true 2>/dev/null || { echo "SKIPPED: strace cannot trace here"; exit 77; }
"$exe" conemap --height builtin:bumps@64 --out r.png --json r.json --no-cache > /dev/null || exit 1
old=$(cat r.png r.json | cksum)
strace -f -qq -o /dev/null -e trace=rename,renameat,renameat2 \
    -e inject=rename,renameat,renameat2:delay_enter=4000000:when=1 \
    sh -c 'echo $$ > pid && exec "$0" "$@"' "$exe" conemap --height builtin:noise@64 --out r.png --json r.json \
    --no-cache > /dev/null &
tracer=$!
tries=0
until [ "$(ls -A | grep -c '\.tmp[0-9]*$')" = 2 ]; do
    tries=$((tries + 1))
    if [ $tries -gt 1200 ]; then echo "the two temporaries did not appear"; kill "$(cat pid)"; exit 1; fi
    sleep 0.05
done
sleep 1 # within the first rename's delay
kill -s TERM "$(cat pid)"
wait $tracer
status=$?
if [ "$status" != 143 ]; then echo "exit status $status, expected 143"; exit 1; fi
if [ -n "$(ls -A | grep '\.tmp')" ]; then echo "temporary left behind"; exit 1; fi
"$exe" conemap --height builtin:noise@64 --out n.png --json n.json --no-cache > /dev/null || exit 1
if [ "$(cat r.png r.json | cksum)" = "$old" ]; then echo "both outputs are the old ones"; exit 1; fi
cmp -s r.png n.png || { echo "r.png is not the new map"; exit 1; }
sed -e 's/"n.png"/"r.png"/' -e '/"ms":/d' n.json > n.cmp && sed '/"ms":/d' r.json | cmp -s - n.cmp ||
    { echo "r.json is not the new report"; diff n.cmp r.json; exit 1; }
echo "both outputs new, died of SIGTERM after the commit"
]])
add_test(NAME cli.signal_during_commit_together_waits_for_both
         COMMAND sh ${pr_output_helpers}/commit_deferral.sh $<TARGET_FILE:prismrelief> ${PR_CLI_WORK}/commit_deferral)
set_tests_properties(cli.signal_during_commit_together_waits_for_both PROPERTIES LABELS "cli" TIMEOUT 180 SKIP_RETURN_CODE 77)

foreach(case "output_folder;TERM;143;.;--no-cache" "cache_folder;HUP;129;c/cone;--cache-dir;c")
    list(POP_FRONT case where sig status folder)
    add_test(NAME cli.signal_removes_temporary_in_${where}
             COMMAND sh ${pr_output_helpers}/signal_cleanup.sh $<TARGET_FILE:prismrelief>
                     ${PR_CLI_WORK}/signal_${where} ${sig} ${status} ${folder}
                     conemap --height builtin:noise@64 --out r.png ${case})
    set_tests_properties(cli.signal_removes_temporary_in_${where}
                         PROPERTIES LABELS "cli" TIMEOUT 180 SKIP_RETURN_CODE 77)
endforeach()

# Flags override the file: --elevation over a scene's camera.eye frames the scene from that
# elevation (it was refused, while --eye over a scene's elevation was taken). The picture is the
# same as the scene without its eye at that elevation.
pr_output_cli(elevation_overrides_scene_eye EXIT 0 EXPECT_FILE a.png
              SETUP "printf '{\"objects\":[{\"mesh\":\"${M}/torus.obj\"}],\"camera\":{\"eye\":[3,2,3],\"target\":[0,0,0]}}' > e.json && printf '{\"objects\":[{\"mesh\":\"${M}/torus.obj\"}],\"camera\":{\"target\":[0,0,0]}}' > n.json && $<TARGET_FILE:prismrelief> render --scene n.json --elevation 60 --size 48x32 --out b.png > /dev/null"
              AFTER "cmp a.png b.png"
              ARGS render --scene e.json --elevation 60 --size 48x32 --out a.png)

# --no-cache for the drawing commands (conemap had it alone): a cone render leaves nothing in the
# cache folder; without the flag it leaves the map there.
foreach(flag no_cache cache)
    set(extra "")
    set(after "test -d xdg/prismrelief/cone")
    if(flag STREQUAL "no_cache")
        set(extra "--no-cache")
        set(after "test ! -e xdg/prismrelief")
    endif()
    pr_output_cli(render_${flag}_cone_entry EXIT 0 EXPECT_FILE o.png
                  ENV XDG_CACHE_HOME=${PR_CLI_WORK}/render_${flag}_cone_entry/xdg
                  SETUP "rm -rf xdg" AFTER "${after}"
                  ARGS render --mesh ${M}/torus.obj --height builtin:bumps@32 --technique cone ${extra} --size 16x16 --out o.png)
endforeach()

# A scene far from the origin, with an explicit camera, draws what the same scene draws at the
# origin, to the bit: the translation, --eye and --target are double (seventeenth session). In
# floats the translation 12345678.9 was 0.1 off and the eye 0.5 off, and the torus moved.
pr_output_cli(far_scene_with_eye_draws_as_at_the_origin EXIT 0 EXPECT_FILE far.png
              SETUP "printf '{\"objects\":[{\"mesh\":\"${M}/torus.obj\",\"transform\":{\"translate\":[12345678.9,12345678.9,0]}}]}' > far.json && $<TARGET_FILE:prismrelief> render --mesh ${M}/torus.obj --technique prism --eye 2.1,1.6,4 --target 0,0,0 --size 48x32 --out near.png > /dev/null"
              AFTER "cmp near.png far.png"
              ARGS render --scene far.json --technique prism --eye 12345681,12345680.5,4 --target 12345678.9,12345678.9,0 --size 48x32 --out far.png)

# An output that is the cone-map cache's folder, or its entries' folder, is refused before the
# work: the output check found nothing there, the run built the map, the cache created the folder,
# and only then "cz: is a folder" (3.7 s for a relaxed 512² map; found by an exploratory session).
pr_output_cli(conemap_out_is_the_cache_folder_refused EXIT 1 ONE_LINE
              STDERR "${E}cz: is the cone-map cache's folder \\(cz\\), which the run creates: name a file, or another --cache-dir"
              SETUP "rm -rf cz" AFTER "test ! -e cz"
              ARGS conemap --height builtin:noise@512 --kind relaxed --out cz --cache-dir cz)
# (With a trailing slash it was "a folder the cone-map cache is in"; thirty-sixth session.)
pr_output_cli(conemap_out_is_the_cache_folder_with_slash_refused EXIT 1 ONE_LINE
              STDERR "${E}cz: is the cone-map cache's folder \\(cz/\\), which the run creates"
              SETUP "rm -rf cz" AFTER "test ! -e cz"
              ARGS conemap --height builtin:noise@64 --out cz --cache-dir cz/)
pr_output_cli(conemap_out_above_the_cache_folder_refused EXIT 1 ONE_LINE
              STDERR "${E}cz: is a folder the cone-map cache is in \\(cz/sub\\), which the run creates"
              SETUP "rm -rf cz" AFTER "test ! -e cz"
              ARGS conemap --height builtin:noise@64 --out cz --cache-dir cz/sub)
# An output in the entries' folder, a file there or not, is refused: `--out` naming the entry the
# run reads wrote the PNG over it, and the next run warned of a bad header and built the map again
# (found by an exploratory session). The file is left as it was.
pr_output_cli(conemap_out_is_a_cache_entry_refused EXIT 1 ONE_LINE
              STDERR "${E}cz/cone/entry.bin: is in the cone-map cache's entries' folder \\(cz/cone\\), whose files the cache replaces"
              SETUP "rm -rf cz && mkdir -p cz/cone && echo x > cz/cone/entry.bin" AFTER "grep -qx x cz/cone/entry.bin"
              ARGS conemap --height builtin:noise@32 --out cz/cone/entry.bin --cache-dir cz)
pr_output_cli(render_out_in_the_cache_entries_folder_refused EXIT 1 ONE_LINE
              STDERR "${E}cz/cone/o.png: is in the cone-map cache's entries' folder"
              SETUP "rm -rf cz && mkdir -p cz/cone" AFTER "test ! -e cz/cone/o.png"
              ARGS render --mesh ${M}/cube.obj --technique cone --size 16x16 --cache-dir cz --out cz/cone/o.png)
pr_output_cli(render_out_is_the_cache_entries_folder_refused EXIT 1 ONE_LINE
              STDERR "${E}xdg/prismrelief/cone: is the cone-map cache's entries' folder \\(/.*/xdg/prismrelief/cone\\)"
              ENV XDG_CACHE_HOME=${PR_CLI_WORK}/render_out_is_the_cache_entries_folder_refused/xdg
              SETUP "rm -rf xdg && mkdir -p xdg/prismrelief" AFTER "test ! -e xdg/prismrelief/cone"
              ARGS render --mesh ${M}/cube.obj --technique cone --size 16x16 --out xdg/prismrelief/cone)

# A run that reads no cone map never creates the cache: an output where the default cache would
# be is a file like any other (it was refused, "which the run creates"; thirty-sixth session).
pr_output_cli(render_out_in_the_cache_place_without_cone_maps EXIT 0 EXPECT_FILE xdg/prismrelief
              ENV XDG_CACHE_HOME=${PR_CLI_WORK}/render_out_in_the_cache_place_without_cone_maps/xdg
              SETUP "rm -rf xdg && mkdir -p xdg" AFTER "test -f xdg/prismrelief"
              ARGS render --mesh ${M}/cube.obj --technique pom --size 16x16 --out xdg/prismrelief)
# The cache's flags are taken where nothing reads a cone map (where derived data may live, not
# what is drawn: a script gives them to every technique of a loop), and such a run creates no
# cache.
pr_output_cli(cache_flags_taken_without_cone_maps EXIT 0 EXPECT_FILE o.png
              SETUP "rm -rf c" AFTER "test ! -e c"
              ARGS render --mesh ${M}/cube.obj --technique relief --cache-dir c --size 16x16 --out o.png)
# "-" is no standard output: a file named "-" was written in the working folder.
pr_output_cli(out_dash_refused EXIT 1 ONE_LINE NO_FILE -
              STDERR "${E}-: is not standard output here: every output is a file written whole and renamed into place"
              ARGS render --mesh ${M}/cube.obj --size 16x16 --out -)
# Nor standard input, where no file of that name is there ("cannot open: No such file or
# directory"; an exploratory session, forty-ninth).
pr_output_cli(height_dash_is_not_stdin EXIT 1 ONE_LINE NO_FILE o.png
              STDERR "${E}--height: -: is not standard input here: name a file \\(/dev/stdin reads standard input"
              ARGS conemap --height - --no-cache --out o.png)
# A name past the file system's limit on a name, or a path past the system's, is refused before
# the work (a 256-byte name: a 40 s relaxed cone map, then "File name too long").
string(REPEAT "a" 252 pr_long_name)
pr_output_cli(conemap_out_name_too_long_refused_early EXIT 1 ONE_LINE TIMEOUT 5
       STDERR "${E}${pr_long_name}.png: cannot write: its name is 256 bytes, more than the 255 a file name may have here"
       ARGS conemap --height builtin:noise@1024 --kind relaxed --no-cache --out ${pr_long_name}.png)
# A folder that takes no new file though root may write there (/proc): refused before the work,
# where the render was drawn and the rename failed ("cannot write: No such file or directory";
# found by an exploratory session). Root only: anyone else is refused by the permission check.
pr_output_cli(out_in_proc_refused_early EXIT 1 ONE_LINE NO_FILE /proc/prismrelief_out.png
              SETUP "[ $(id -u) -eq 0 ] || exit 77"
              STDERR "${E}/proc/prismrelief_out.png: cannot write in folder /proc: it takes no new file \\(a file system such as /proc or /sys\\)"
              ARGS render --mesh ${M}/cube.obj --size 8x8 --out /proc/prismrelief_out.png)

