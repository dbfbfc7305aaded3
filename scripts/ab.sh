#!/usr/bin/env bash
# A/B timing of two builds or two sets of shaders, alternated run by run on the bundled meshes
# (machines are noisy: compare the ratios within each run, and their medians). Each run is one
# `prismrelief bench` of `pom` and TECHNIQUES; a side is a binary, or `shaders:DIR` for the
# default binary with PRISMRELIEF_SHADER_DIR=DIR (a copy of shaders/ with a change, or an old
# revision's: `git archive REV shaders | tar -x -C DIR`, then DIR/shaders). Prints, per mesh and
# side, the median time of each technique and of its ratio to `pom`.
#
#   [RUNS=4] [SIZE=1280x720] [FRAMES=8] [WARMUP=2] [TECHNIQUES=prism:relaxed-cone,prism]
#   [MESHES="torus.obj rock.obj ..."] [BACKEND=osmesa|egl] [PRISMRELIEF=exe] scripts/ab.sh A B
#
# Used for the twenty-sixth session's figures (docs/benchmarks.md), on llvmpipe and on a GPU.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: scripts/ab.sh A B (a binary, or shaders:DIR)" >&2; exit 1; }
exe=$(realpath -m "${PRISMRELIEF:-$(dirname "$0")/../build/src/prismrelief}")
side() { # side SPEC -> "EXE SHADER_DIR" (resolved from the caller's folder)
    if [[ $1 == shaders:* ]]; then echo "$exe $(realpath -m "${1#shaders:}")"; else echo "$(realpath -m "$1") -"; fi
}
read -r exe_a dir_a <<<"$(side "$1")"
read -r exe_b dir_b <<<"$(side "$2")"
cd "$(dirname "$0")/.."
runs=${RUNS:-4}
techniques=${TECHNIQUES:-prism:relaxed-cone,prism}
meshes=${MESHES:-torus.obj rock.obj blob.off uv_sphere.obj cube.obj plane.obj}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for ((r = 1; r <= runs; ++r)); do
    for mesh in $meshes; do
        for s in a b; do
            if [ $s = a ]; then e=$exe_a d=$dir_a; else e=$exe_b d=$dir_b; fi
            envs=()
            [ "$d" = - ] || envs=(PRISMRELIEF_SHADER_DIR="$d")
            env "${envs[@]}" "$e" bench \
                --backend "${BACKEND:-osmesa}" --mesh "meshes/$mesh" --height builtin:bumps \
                --size "${SIZE:-1280x720}" --frames "${FRAMES:-8}" --warmup "${WARMUP:-2}" \
                --techniques "pom,$techniques" --json "$work/$mesh.$s.$r.json" >/dev/null
        done
    done
done

python3 - "$work" "$1" "$2" "$meshes" <<'EOF'
import glob, json, os, statistics, sys
work, name_a, name_b, meshes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split()
print(f"A = {name_a}, B = {name_b}: medians over the runs, ms (ratio to pom)")
for mesh in meshes:
    for side, name in (("a", "A"), ("b", "B")):
        runs = [json.load(open(f))["results"] for f in sorted(glob.glob(os.path.join(work, f"{mesh}.{side}.*.json")))]
        cells = []
        for i, row in enumerate(runs[0]):
            ms = statistics.median(r[i]["ms_median"] for r in runs)
            ratio = statistics.median(r[i]["ms_median"] / r[0]["ms_median"] for r in runs)
            cells.append(f"{row['technique']} {ms:.2f}" + ("" if i == 0 else f" ({ratio:.3f})"))
        print(f"{mesh:14s} {name}: " + ", ".join(cells))
EOF
