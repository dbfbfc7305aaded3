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
pr_cli(render_out_over_height_map EXIT 1 ONE_LINE STDERR "${E}--out: keep.png is the --height input" KEEP_FILE keep.png
       ARGS render --mesh ${M}/cube.obj --height keep.png --size 32x32 --out keep.png)
pr_cli(bench_json_over_scene EXIT 1 ONE_LINE STDERR "${E}--json: keep.json is the --scene input" KEEP_FILE keep.json
       ARGS bench --scene keep.json --techniques pom --size 32x32 --frames 1 --json keep.json)

# PNG data under another format's name.
pr_cli(render_out_jpg EXIT 1 ONE_LINE STDERR "${E}o.jpg: only PNG images are written" NO_FILE o.jpg
       ARGS render --mesh ${M}/cube.obj --size 32x32 --out o.jpg)
pr_cli(conemap_out_tga EXIT 1 ONE_LINE STDERR "${E}c.TGA: only PNG images are written" NO_FILE c.TGA
       ARGS conemap --height builtin:bumps@16 --out c.TGA --no-cache)

# A few covered pixels of a large image are not "coverage 0.0%".
pr_cli(render_small_coverage_has_digits EXIT 0 EXPECT_FILE o.png STDOUT "coverage 0\\.0[0-9][0-9][1-9]%"
       ARGS render --mesh ${M}/torus.obj --size 4096x16 --out o.png)

# Reports say which prism they measured: a row labelled "prism" holds --marcher's choice.
pr_cli(compare_json_names_the_prism_configuration EXIT 0 JSON c.json
       CHECKS "results.0.technique:STREQUAL:prism|results.0.marcher:STREQUAL:max-mip|results.0.prism_exit:STREQUAL:walk|results.0.prism_shell:STREQUAL:tight|results.1.prism_exit:STREQUAL:exact|results.1.prism_shell:STREQUAL:full|camera.up.1:EQUAL:1"
       ARGS compare --mesh ${M}/cube.obj --techniques prism,prism:linear:exact --marcher max-mip --size 32x32 --json c.json)
pr_cli(bench_json_names_the_prism_configuration EXIT 0 JSON b.json
       CHECKS "results.0.marcher:STREQUAL:cone|results.0.prism_shell:STREQUAL:full"
       ARGS bench --mesh ${M}/cube.obj --techniques prism:cone --prism-shell full --size 32x32 --frames 1 --json b.json)
