#!/usr/bin/env bash
# Watertightness of the prism against the reference (docs/prism.md): for the nine views of
# scripts/accuracy.sh (512x512, builtin:bumps, outward), the number of background pixels that the
# technique leaves inside the reference's outline — pixels the reference covers, as it does every
# pixel within 2 (the 5x5 block around it: the issue's tests allow 2 pixels of difference at the
# outline, inner outlines included), and the technique does not. Prints a Markdown table.
# Usage: [TECHNIQUES="prism prism:relief:exact"] [PRISMRELIEF=exe] [FLAGS="--backend egl"] scripts/watertight.sh
set -euo pipefail
cd "$(dirname "$0")/.."
pr=${PRISMRELIEF:-build/src/prismrelief}
techniques=${TECHNIQUES:-prism prism:relief:exact}
read -r -a flags <<<"${FLAGS:-}"  # extra flags for every render (--backend egl)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| mesh | elevation | technique | reference interior px | background in technique px |"
echo "|---|---|---|---|---|"
for mesh in uv_sphere torus rock; do
    for el in 0 35 75; do
        "$pr" render --mesh "meshes/$mesh.obj" --height builtin:bumps --size 512x512 --elevation "$el" \
            --technique reference ${flags[@]+"${flags[@]}"} --out "$tmp/ref.png" >/dev/null 2>&1
        for t in $techniques; do
            # prism:MARCHER:EXIT:SHELL as --marcher/--prism-exit/--prism-shell flags (render
            # takes one technique)
            IFS=: read -r name marcher exit shell <<<"$t"
            args=(--technique "$name")
            [ -n "${marcher:-}" ] && args+=(--marcher "$marcher")
            [ -n "${exit:-}" ] && args+=(--prism-exit "$exit")
            [ -n "${shell:-}" ] && args+=(--prism-shell "$shell")
            "$pr" render --mesh "meshes/$mesh.obj" --height builtin:bumps --size 512x512 --elevation "$el" \
                "${args[@]}" ${flags[@]+"${flags[@]}"} --out "$tmp/t.png" >/dev/null 2>&1
            python3 - "$tmp/ref.png" "$tmp/t.png" "$mesh" "$el" "$t" <<'PY'
import sys
sys.path.insert(0, "scripts")
from pngio import read_png8
w, h, c, ref = read_png8(sys.argv[1])
_, _, _, tech = read_png8(sys.argv[2])
covered = lambda rows, x, y: rows[y][x * c + c - 1] >= 128
inner = holes = 0
for y in range(2, h - 2):
    for x in range(2, w - 2):
        if all(covered(ref, x + dx, y + dy) for dx in range(-2, 3) for dy in range(-2, 3)):
            inner += 1
            holes += not covered(tech, x, y)
print(f"| {sys.argv[3]} | {sys.argv[4]}° | {sys.argv[5]} | {inner} | {holes} |")
PY
        done
    done
done
