#!/usr/bin/env bash
# Prism accuracy table (docs/prism.md): compare at 512x512 on the bundled curved meshes,
# outward bumps with depth 4% of the bounding-box diagonal (the default), from three auto-framed
# elevations. Prints a Markdown table. Usage: [TECHNIQUES=a,b,...] [PRISMRELIEF=exe] scripts/accuracy.sh [extra compare flags]
set -euo pipefail
cd "$(dirname "$0")/.."
pr=${PRISMRELIEF:-build/src/prismrelief}
techniques=${TECHNIQUES:-pom,prism,prism:linear,prism:relief:walk:full,prism:relief:exact,prism:relief:vertex}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| mesh | elevation | technique | IoU | silhouette px wrong | only in reference px | depth error mean (% of depth) | median (% of depth) | max |"
echo "|---|---|---|---|---|---|---|---|---|"
for mesh in uv_sphere torus rock; do
    for el in 0 35 75; do
        "$pr" compare --mesh "meshes/$mesh.obj" --height builtin:bumps --size 512x512 --elevation "$el" \
            --techniques "$techniques" --json "$tmp/r.json" "$@" >/dev/null
        python3 - "$tmp/r.json" "$mesh" "$el" "meshes/$mesh.obj" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
# depth = 4% of the mesh's bounding-box diagonal (prismrelief's default)
lo = [1e30] * 3; hi = [-1e30] * 3
for line in open(sys.argv[4]):
    if line.startswith('v '):
        p = [float(x) for x in line.split()[1:4]]
        lo = [min(a, b) for a, b in zip(lo, p)]; hi = [max(a, b) for a, b in zip(hi, p)]
depth = 0.04 * sum((b - a) ** 2 for a, b in zip(lo, hi)) ** 0.5
for t in r["results"]:
    print(f"| {sys.argv[2]} | {sys.argv[3]}° | {t['technique']} | {t['iou']:.4f} | {t['silhouette_wrong_px']} | "
          f"{t['only_in_reference_px']} | {100 * t['depth_error_mean'] / depth:.2f} | "
          f"{100 * t['depth_error_median'] / depth:.2f} | {t['depth_error_max']:.3f} |")
PY
    done
done
