#!/usr/bin/env bash
# The cone marchers against the relief marcher on sheer-edged height maps (docs/cone-maps.md,
# refine_cone; twenty-eighth session): the bundled plane, seen low over it from four eyes, 192x144,
# each view compared with the reference. Maps: a mesa, slots two texels wide, terraces (512^2),
# fins 2 texels wide (1024x64), a wall 4 texels thick (2048x32), builtin:boxes and builtin:bricks.
# Prints each view's PSNR / outline pixels wrong per technique, and the sum over the views of the
# dB by which each cone marcher falls short of the relief marcher (views more than 3 dB short).
# Usage: [PRISMRELIEF=exe] scripts/sheer_sweep.sh
set -euo pipefail
cd "$(dirname "$0")/.."
pr=$(realpath -m "${PRISMRELIEF:-build/src/prismrelief}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp" <<'PY'
import math, sys
sys.path.insert(0, "scripts")
from pngio import write_png
def save(name, w, h, f):
    write_png(f"{sys.argv[1]}/{name}.png", w, [bytes(round(255 * f(x, y)) for x in range(w)) for y in range(h)])
save("mesa", 512, 512, lambda x, y: 0.9 if (x - 256) ** 2 + (y - 256) ** 2 < 120 ** 2 else 0.1)
save("slots", 512, 512, lambda x, y: 0.0 if x % 32 < 2 else 1.0)
save("terraces", 512, 512, lambda x, y: math.floor(x / 64) / 8)
save("fins", 1024, 64, lambda x, y: 1.0 if x % 128 < 2 else 0.0)
save("wall", 2048, 32, lambda x, y: 1.0 if 1024 <= x < 1028 else 0.0)
PY
techniques=prism,prism:cone,prism:relaxed-cone
for map in mesa slots terraces fins wall builtin:boxes builtin:bricks; do
    height=$map
    [[ $map == builtin:* ]] || height="$tmp/$map.png"
    for eye in 0.6,0.15,0.3 -0.5,0.12,0.6 0.2,0.4,0.9 0.9,0.1,-0.2; do
        "$pr" compare --mesh meshes/plane.obj --height "$height" --size 192x144 --eye "$eye" --target 0,0.03,0 \
            --techniques "$techniques" --json "$tmp/r.json" >/dev/null
        python3 -c '
import json, sys
r = {t["technique"]: t for t in json.load(open(sys.argv[1]))["results"]}
psnr = lambda t: min(r[t]["psnr"] if r[t]["psnr"] is not None else 99.0, 99.0)
print(sys.argv[2], sys.argv[3], *("%s %.1f %d" % (t, psnr(t), r[t]["silhouette_wrong_px"]) for t in r))
' "$tmp/r.json" "${map#builtin:}" "$eye"
    done
done | tee "$tmp/views.txt"
python3 - "$tmp/views.txt" <<'PY'
import sys
short = {}
for line in open(sys.argv[1]):
    f = line.split()
    vals = {f[i]: float(f[i + 1]) for i in range(2, len(f), 3)}
    for t in ("prism:cone", "prism:relaxed-cone"):
        d = max(0.0, vals["prism"] - vals[t])
        total, views = short.get(t, (0.0, 0))
        short[t] = (total + d, views + (d > 3.0))
for t, (total, views) in short.items():
    print(f"{t}: {total:.1f} dB short of the relief marcher over the views, {views} views by more than 3 dB")
PY
