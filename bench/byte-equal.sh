#!/usr/bin/env bash
# Holds a change to "byte-equal": the ledgers and pictures of every SCENES.md scene at both SIMD
# levels, and `analyze --frames --report` of the ten glmark2 captures, written by one binary,
# compared with another's.
#
#   bench/byte-equal.sh run BIN OUT       # write BIN's outputs into OUT
#   bench/byte-equal.sh diff OUT1 OUT2    # compare two such folders; exit 1 if they differ
#
# Build the binaries with `cargo build --release -p tiler-cli` and copy each away: a binary built
# with `--all-targets` or by a workspace-wide `cargo test --release` checks every texture read
# against the reference model (docs/benchmarking.md, "Profiling"). Timings, host-memory peaks
# and the lines naming an output path are left out of the comparison. Needs ../shared (or
# $TILER_ASSETS and $TILER_TRACES) and python3.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
assets=${TILER_ASSETS:-$here/../shared/assets}
traces=${TILER_TRACES:-$here/../shared/traces/glmark2}

strip_json() {
    python3 - "$1" <<'PY'
import json, re, sys
path = sys.argv[1]
def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items()
                if not re.search('fps|per_s|peak_host|host|time|_ms|ms_|seconds|elapsed|duration', k)}
    if isinstance(o, list):
        return [strip(x) for x in o]
    return o
data = strip(json.load(open(path)))
json.dump(data, open(path, 'w'), indent=1, sort_keys=True)
PY
}

run() {
    local bin=$1 out=$2
    mkdir -p "$out"
    scene() {
        local name=$1; shift
        for simd in baseline avx2; do
            "$bin" bench "$@" --simd "$simd" --frames 1 --warmup 0 --threads 2 --size 960x540 \
                --assets "$assets" --json --out "$out/$name-$simd" > "$out/$name-$simd.json"
            strip_json "$out/$name-$simd.json"
        done
    }
    scene clear --scene clear
    scene clear4 --scene clear --msaa 4
    scene helmet --scene helmet
    scene helmet4 --scene helmet --msaa 4
    scene atrium --scene atrium
    scene overdraw-tbr --scene overdraw --backend tbr
    scene overdraw-imr --scene overdraw --backend imr
    scene overdraw-tbdr --scene overdraw --backend tbdr
    scene overdraw-tbdr4 --scene overdraw --backend tbdr --msaa 4 --tile 16
    scene helmet-tbdr --scene helmet --backend tbdr --tile 64
    scene f2b --scene overdraw_f2b
    scene tris-tbr --scene tris --backend tbr
    scene tris-imr --scene tris --backend imr
    for trace in "$traces"/*.trace; do
        local n
        n=$(basename "$trace" .trace)
        "$bin" analyze "$trace" --frames "$out/trace-$n" --report "$out/trace-$n.json" \
            | grep -v "report →" > "$out/trace-$n.txt"
        strip_json "$out/trace-$n.json"
    done
}

compare() {
    local a=$1 b=$2 bad=0 f
    while IFS= read -r f; do
        cmp -s "$a/$f" "$b/$f" || { echo "differs: $f"; bad=1; }
    done < <(cd "$a" && find . -type f | sort)
    while IFS= read -r f; do
        [ -e "$a/$f" ] || { echo "only in $b: $f"; bad=1; }
    done < <(cd "$b" && find . -type f | sort)
    if [ $bad = 0 ]; then echo "byte-equal"; else echo "NOT byte-equal"; exit 1; fi
}

case "${1:-}" in
    run) run "${2:?binary}" "${3:?output folder}" ;;
    diff) compare "${2:?first folder}" "${3:?second folder}" ;;
    *) sed -n '2,14p' "$0"; exit 2 ;;
esac
