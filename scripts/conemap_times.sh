#!/usr/bin/env bash
# Times `prismrelief conemap` on every built-in height map and on pathological ones, at 512² and
# 1024², cone and relaxed, CPU (all cores) and GPU (compute shader; llvmpipe unless --gl-backend
# egl finds a GPU), and the GPU's dispatches alone. Prints a Markdown table for docs/cone-maps.md.
# Nothing is cached.
#
#   [GL_BACKEND=egl] scripts/conemap_times.sh [build/src/prismrelief] [sizes...]      e.g. ... build/src/prismrelief 512
#
# GL_BACKEND=egl runs the GPU rows through EGL (a real GPU where one is found).
set -euo pipefail
exe=${1:-build/src/prismrelief}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(512 1024)
gl=()
[ -n "${GL_BACKEND:-}" ] && gl=(--gl-backend "$GL_BACKEND")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Pathological maps as 16-bit PNGs (standard library only): a single spike on a flat floor (every
# texel's nearest higher texel is far: ring searches see the whole map), a step, a ramp, a hill
# (a cone across the map: like the ramp, many far texels limit a cone almost equally), white
# noise (every texel has a higher neighbour: tiny cones, the cheapest case for pruning).
python3 - "$work" "$(dirname "$0")" "${sizes[@]}" <<'EOF'
import random, struct, sys
out, scripts, sizes = sys.argv[1], sys.argv[2], [int(s) for s in sys.argv[3:]]
sys.path.insert(0, scripts)
from pngio import write_png
def png16(path, n, f):
    write_png(path, n, [b"".join(struct.pack(">H", int(round(max(0.0, min(1.0, f(x, y))) * 65535))) for x in range(n))
                        for y in range(n)], bit_depth=16)
for n in sizes:
    rnd = random.Random(7)
    png16(f"{out}/spike{n}.png", n, lambda x, y: 1.0 if (x, y) == (n // 3, n // 2) else 0.0)
    png16(f"{out}/step{n}.png", n, lambda x, y: 1.0 if x >= n // 2 else 0.0)
    png16(f"{out}/ramp{n}.png", n, lambda x, y: x / (n - 1))
    png16(f"{out}/hill{n}.png", n, lambda x, y: 1.0 - 2.0 * ((x + 0.5 - n / 2) ** 2 + (y + 0.5 - n / 2) ** 2) ** 0.5 / n)
    png16(f"{out}/white{n}.png", n, lambda x, y: rnd.random())
EOF

# Compile the compute shaders once before timing (Mesa keeps them in its shader cache, as it does
# for every later run of a user's): the first GPU row would otherwise include compiling them.
for kind in cone relaxed; do
    "$exe" conemap --height builtin:bumps@16 --kind "$kind" --backend gpu ${gl[@]+"${gl[@]}"} --no-cache --out "$work/o.png" >/dev/null
done

echo "| height map | size | cone cpu s | relaxed cpu s | cone gpu s | relaxed gpu s | cone gpu search s | relaxed gpu search s |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
    for map in bumps bricks noise pyramids boxes const:0.5 spike step ramp hill white; do
        case $map in
            spike|step|ramp|hill|white) height=$work/$map$n.png; label="$map (file)";;
            *) height=builtin:$map@$n; label=$map;;
        esac
        row="| $label | $n"
        search=""
        for backend in cpu gpu; do
            for kind in cone relaxed; do
                extra=()
                [ "$backend" = gpu ] && extra=(${gl[@]+"${gl[@]}"})
                "$exe" conemap --height "$height" --kind "$kind" --backend "$backend" ${extra[@]+"${extra[@]}"} --no-cache \
                    --out "$work/o.png" --json "$work/o.json" >/dev/null
                row+=" | $(python3 -c "import json,sys; print(f\"{json.load(open(sys.argv[1]))['ms'] / 1000:.2f}\")" "$work/o.json")"
                # the GPU's dispatches alone, without the context, upload and compiling
                if [ "$backend" = gpu ]; then
                    search+=" | $(python3 -c "import json,sys; print(f\"{json.load(open(sys.argv[1]))['search_ms'] / 1000:.2f}\")" "$work/o.json")"
                fi
            done
        done
        # columns were produced cpu-cone, cpu-relaxed, gpu-cone, gpu-relaxed: the header's order
        echo "$row$search |"
    done
done
