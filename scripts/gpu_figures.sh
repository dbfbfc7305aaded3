#!/usr/bin/env bash
# The GPU figures of docs/benchmarks.md (its sections on an H200 and the H100s) on a machine with a
# GPU, through EGL: frame times of flat, pom, relief, the cone marchers, the prism's variants and
# reference at 1280x720 on the bundled meshes and scenes (with and without shadows), the prism
# accuracy and watertightness tables, cone-map generation on the CPU's threads against the compute
# shader, the tiles of one compare view to set beside llvmpipe's, and where the prism's time goes
# (its walk with the least march: `--steps 1`, linear). Each step has a time limit
# and its own log, so a step that fails leaves the others' figures.
#
#   [PRISMRELIEF=exe] [SIZE=1280x720] [FRAMES=30] [WARMUP=5] [STEPS="bench shadows ..."] \
#       scripts/gpu_figures.sh OUTDIR
set -uo pipefail
# OUTDIR and PRISMRELIEF relative to the caller's folder (the script works from the repository's).
out=$(realpath -m "${1:?usage: scripts/gpu_figures.sh OUTDIR}")
exe=$(realpath -m "${PRISMRELIEF:-$(dirname "$0")/../build/src/prismrelief}")
cd "$(dirname "$0")/.."
size=${SIZE:-1280x720}
frames=${FRAMES:-30}
warmup=${WARMUP:-5}
steps=${STEPS:-smoke tiles bench decompose shadows conemap accuracy scenes watertight}
mkdir -p "$out"
export PRISMRELIEF="$exe"

# step NAME SECONDS COMMAND...: runs COMMAND with its output in OUTDIR/NAME.txt, says how it went
step() {
    local name=$1 limit=$2
    shift 2
    local t0=$SECONDS
    timeout "$limit" "$@" >"$out/$name.txt" 2>&1
    local rc=$?
    echo "$name: rc $rc, $((SECONDS - t0)) s"
    [ $rc -eq 0 ] || tail -n 5 "$out/$name.txt" | sed 's/^/    /'
}
wanted() { [[ " $steps " == *" $1 "* ]]; }

all=flat,pom,relief,cone,relaxed-cone,prism,prism:relaxed-cone,prism:cone,prism:max-mip,prism:linear,prism:relief:exact,reference
bench=("$exe" bench --backend egl --size "$size" --frames "$frames" --warmup "$warmup")

if wanted smoke; then
    step smoke 60 "$exe" render --backend egl --mesh meshes/torus.obj --technique prism --size 256x192 \
        --out "$out/smoke.png" --json "$out/smoke.json"
fi
if wanted tiles; then
    mkdir -p "$out/tiles"
    step tiles 60 "$exe" compare --backend egl --mesh meshes/torus.obj --size 256x192 --elevation 35 \
        --techniques pom,relief,relaxed-cone,prism,prism:relaxed-cone --tiles "$out/tiles" \
        --out "$out/tiles/grid.png" --json "$out/tiles/compare.json"
fi
if wanted bench; then
    for mesh in torus.obj rock.obj blob.off uv_sphere.obj cube.obj plane.obj; do
        step "bench_${mesh%.*}" 120 "${bench[@]}" --mesh "meshes/$mesh" --techniques "$all" \
            --json "$out/bench_${mesh%.*}.json"
    done
fi
if wanted decompose; then
    for mesh in torus rock; do
        step "decompose_$mesh" 120 "${bench[@]}" --mesh "meshes/$mesh.obj" --steps 1 \
            --techniques flat,pom,prism:linear,prism:linear:walk:full,prism:linear:exact --json "$out/decompose_$mesh.json"
    done
fi
if wanted shadows; then
    for mesh in torus rock; do
        for s in hard soft; do
            step "shadows_${mesh}_$s" 120 "${bench[@]}" --mesh "meshes/$mesh.obj" --shadows "$s" \
                --techniques pom,relief,relaxed-cone,prism,prism:relaxed-cone,reference \
                --json "$out/shadows_${mesh}_$s.json"
        done
    done
fi
if wanted conemap; then
    step conemap 240 env GL_BACKEND=egl scripts/conemap_times.sh "$exe" 512 1024
fi
if wanted accuracy; then
    step accuracy 180 scripts/accuracy.sh --backend egl
fi
if wanted scenes; then
    for scene in meshes/scenes/*.json; do
        name=$(basename "$scene" .json)
        step "scene_$name" 120 "${bench[@]}" --scene "$scene" \
            --techniques pom,relief,relaxed-cone,prism,prism:relaxed-cone,reference --json "$out/scene_$name.json"
    done
fi
if wanted watertight; then
    step watertight 180 env FLAGS="--backend egl" scripts/watertight.sh
fi
