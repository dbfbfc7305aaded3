#!/bin/sh
# Redraws the documentation's figures (docs/images) with the commands the docs give for each, so
# that a change to what the techniques draw can bring them up to date in one run:
#   scripts/figures.sh [BUILD_DIR]      (default build; the viewer's two need xvfb-run)
# Left as they are: prism-crease.png (two crops of a close-up, enlarged by hand) and the left half
# of uv_charts.png (a build from before the charts were tidied: docs/mesh-input.md).
# Rendering is deterministic on one machine and Mesa; another CPU or driver may move a pixel by
# a level. Run from the repository's root; it writes docs/images/*.png and a scratch folder.
set -eu
build=${1:-build}
pr=$build/src/prismrelief
[ -x "$pr" ] || { echo "figures.sh: $pr is not built (scripts/build.sh)" >&2; exit 1; }
img=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export XDG_CACHE_HOME="$tmp/cache"

# docs/techniques.md: each technique on the bricks (--steps only where the technique reads it).
for t in flat normal offset steep pom relief cone relaxed-cone; do
    case $t in flat | normal | offset) steps= ;; *) steps="--steps 24" ;; esac
    # shellcheck disable=SC2086 # (steps: none or two words)
    "$pr" render --mesh meshes/plane.obj --height builtin:bricks --color builtin:bricks \
        --depth 0.1 --eye 0.5,0.75,1.6 --target 0,0,0.1 --size 320x200 $steps \
        --technique "$t" --out "$img/technique-$t.png"
done

# README.md: the default scene (relief on the torus) and the prism on the bundled scene.
"$pr" render --scene meshes/scenes/default.json --size 640x400 --out "$img/default.png"
"$pr" render --scene meshes/scenes/plane_and_torus.json --technique prism --size 640x400 \
    --out "$img/prism-scene.png"

# docs/compare.md: the grid on the torus; hard and soft shadows on the plane of boxes.
"$pr" compare --mesh meshes/torus.obj --height builtin:bumps --techniques pom,prism \
    --size 256x256 --elevation 20 --out "$img/compare-torus.png" --json "$tmp/cmp.json"
"$pr" compare --mesh meshes/plane.obj --height builtin:boxes --depth 0.15 --size 256x192 \
    --light 1,0.6,0.3 --techniques relief,prism,prism:relaxed-cone --shadows hard \
    --eye 0.9,0.9,1.6 --target 0,0,0 --out "$img/compare-shadows.png"
"$pr" compare --mesh meshes/plane.obj --height builtin:boxes --depth 0.15 --size 256x192 \
    --light 1,0.6,0.3 --eye 0.9,0.9,1.6 --target 0,0,0 --techniques prism,prism:relaxed-cone \
    --shadows soft --light-size 12 --out "$img/compare-soft-shadows.png"

# docs/prism.md: the torus with bricks; POM against the prism on the rock.
"$pr" render --mesh meshes/torus.obj --height builtin:bricks --color builtin:bricks \
    --depth 0.1 --technique prism --size 640x400 --elevation 30 --out "$img/prism-torus-bricks.png"
"$pr" compare --mesh meshes/rock.obj --techniques pom,prism --size 320x320 --elevation 10 \
    --out "$img/prism-rock.png"

# docs/cone-maps.md: a height map next to its cone and relaxed maps; shadows none, hard, soft.
"$pr" conemap --height builtin:boxes@256 --format rg8 --out "$tmp/cone.png" --no-cache
"$pr" conemap --height builtin:boxes@256 --format rg8 --kind relaxed --out "$tmp/relaxed.png" --no-cache
python3 scripts/conemap_figure.py "$tmp/cone.png" "$tmp/relaxed.png" "$img/conemap_boxes.png"
for s in none hard soft; do
    "$pr" render --mesh meshes/plane.obj --height builtin:boxes --depth 0.1 \
        --technique relaxed-cone --shadows "$s" --light -1,0.5,0.4 --eye 0.9,1.1,1.3 \
        --target 0.1,0,0.1 --fovy 30 --size 256x192 --out "$tmp/$s.png"
done
python3 scripts/side_by_side.py "$tmp/none.png" "$tmp/hard.png" "$tmp/soft.png" "$img/shadows.png"

# The viewer (a window under Xvfb): the shell overlay (docs/prism.md), the split view (README.md;
# its panel's timings differ from run to run).
if command -v xvfb-run > /dev/null; then
    xvfb-run -a "$pr" view --mesh meshes/cube.obj --height builtin:bumps --depth 0.15 \
        --technique prism --overlay shell --size 640x400 --frames 2 --no-panel \
        --screenshot-ui --screenshot "$img/prism-shell.png"
    xvfb-run -a "$pr" view --scene meshes/scenes/plane_and_torus.json --split pom,prism --divider 0.6 \
        --size 1200x640 --frames 4 --screenshot "$img/viewer_split.png" --screenshot-ui
else
    echo "figures.sh: no xvfb-run: prism-shell.png and viewer_split.png left as they are" >&2
fi
