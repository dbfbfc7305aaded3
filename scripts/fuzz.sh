#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/) with clang, ASan and UBSan into build-fuzz/, and
# runs each one in turn for SECONDS (default 60) on a work corpus seeded from meshes/ and
# tests/bad/ (copied under build-fuzz/, never into the source tree). Prints, per harness: runs,
# exec/s, coverage (cov = edges, ft = features, libFuzzer's final figures) and any crash.
#
#   scripts/fuzz.sh [SECONDS] [fuzz_mesh|fuzz_image|fuzz_scene ...]
#
# Environment: PRISMRELIEF_FUZZ_BUILD (default build-fuzz), FUZZ_JOBS (ninja -j, default 2),
# FUZZ_FRESH=1 to start from the seeds again (otherwise the work corpus grows run after run).
# Exit status: 0 when no harness found anything, 1 otherwise. Crashing inputs are kept under
# build-fuzz/artifacts/<harness>/ (reproduce: build-fuzz/tests/fuzz/<harness> FILE).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
[[ $# -gt 0 ]] && shift
harnesses=("$@")
[[ ${#harnesses[@]} -eq 0 ]] && harnesses=(fuzz_mesh fuzz_image fuzz_scene)
build=${PRISMRELIEF_FUZZ_BUILD:-$root/build-fuzz}

command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is missing (apt-get install clang)" >&2; exit 2; }
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DPRISMRELIEF_FUZZ=ON -DPRISMRELIEF_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "${FUZZ_JOBS:-2}" --target "${harnesses[@]}"

# Seeds: for fuzz_mesh the first byte picks the extension (0 .obj, 1 .off, 2 .ply, 3 .stl).
seed() {
    local h=$1 dir=$2
    mkdir -p "$dir"
    case $h in
    fuzz_mesh)
        local i=0 ext
        for ext in obj off ply stl; do
            for f in "$root"/meshes/*."$ext" "$root"/tests/bad/*."$ext"; do
                [[ -f $f ]] || continue
                { printf "\\x0$i"; head -c 65536 "$f"; } >"$dir/seed-$(basename "$f")"
            done
            i=$((i + 1))
        done ;;
    fuzz_image)
        for f in "$root"/tests/bad/*.png "$root"/tests/bad/*.jpg "$root"/tests/bad/*.bmp \
                 "$root"/tests/bad/*.tga; do
            if [[ -f $f ]]; then cp "$f" "$dir/seed-$(basename "$f")"; fi
        done ;;
    fuzz_scene)
        for f in "$root"/meshes/scenes/*.json "$root"/tests/bad/*.json; do
            if [[ -f $f ]]; then cp "$f" "$dir/seed-$(basename "$f")"; fi
        done ;;
    esac
}

status=0
summary=()
for h in "${harnesses[@]}"; do
    corpus=$build/corpus/$h
    artifacts=$build/artifacts/$h/
    log=$build/logs/$h.log
    [[ ${FUZZ_FRESH:-0} == 1 ]] && rm -rf "$corpus"
    seed "$h" "$corpus"
    mkdir -p "$artifacts" "$(dirname "$log")"
    case $h in
    fuzz_mesh) max_len=65536; extra=() ;;
    fuzz_image) max_len=16384; extra=() ;;
    fuzz_scene) max_len=4096; extra=(-dict="$root/tests/fuzz/scene.dict") ;;
    *) max_len=4096; extra=() ;;
    esac
    echo "== $h: ${seconds}s, corpus $corpus ($(ls "$corpus" | wc -l) files), log $log"
    rc=0
    # -close_fd_mask=3: the code under test prints warnings; libFuzzer keeps its own output
    # and the sanitizers' reports on a duplicate of stderr.
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1} \
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
    "$build/tests/fuzz/$h" "$corpus" -max_total_time="$seconds" -max_len="$max_len" \
        -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -close_fd_mask=3 \
        -artifact_prefix="$artifacts" "${extra[@]}" >"$log" 2>&1 || rc=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    cov=$(grep -Eo 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1)
    corpus_n=$(ls "$corpus" | wc -l)
    if [[ $rc -eq 0 ]]; then
        result="no findings"
    else
        status=1
        result="FINDING (exit $rc): $(grep -Eo '(ERROR|SUMMARY): .*' "$log" | head -1); artifacts in $artifacts"
    fi
    line="$h: ${seconds}s, ${runs:-?} runs, ${rate:-?} exec/s, ${cov:-cov ?}, corpus $corpus_n, $result"
    echo "$line"
    summary+=("$line")
done
echo "== summary"
printf '%s\n' "${summary[@]}"
exit $status
