#!/usr/bin/env bash
# README command 1: installs what is missing, builds, and renders the bundled default scene
# (a torus with bricks) to out/: once large, then with every technique, the prism silhouettes
# and the tessellated reference included.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p out
pr=build/src/prismrelief
"$pr" render --scene meshes/scenes/default.json --out out/default.png
for t in flat normal offset steep pom relief cone relaxed-cone prism reference; do
    "$pr" render --scene meshes/scenes/default.json --technique "$t" --size 400x300 --out "out/default-$t.png"
done
echo "demo: images in out/"
