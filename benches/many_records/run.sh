#!/usr/bin/env bash
# 492 records naming one .npz against 492 CSV files (issue 17: "a file named by several
# records is read once"): `dampid identify` on each model file, wall time and peak memory.
#
#   cargo build --release --bin dampid
#   bash benches/many_records/run.sh [DATA_DIR] [REPEATS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${1:-/tmp/dampid-many-records}
repeats=${2:-3}
bin=${CARGO_TARGET_DIR:-$root/target}/release/dampid
python=${PYTHON:-python3}
[ -f "$data/npz.toml" ] || "$python" "$here/generate.py" "$data"
[ -x "$bin" ] || { echo "build first: cargo build --release --bin dampid" >&2; exit 1; }
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); $(git -C "$root" rev-parse --short HEAD)"
for run in $(seq "$repeats"); do
    for file in npz csv; do
        log=$(mktemp)
        /usr/bin/time -v "$bin" identify "$data/$file.toml" --json >"$log.out" 2>"$log" || { cat "$log" >&2; exit 1; }
        wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$log")
        rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$log")
        c=$("$python" -c "import json,sys; r=json.load(open(sys.argv[1]))['report']; print(r['coefficients'][0]['value'] if isinstance(r['coefficients'], list) else r['coefficients'])" "$log.out" 2>/dev/null || echo "?")
        printf 'run %s  %-4s  %8s wall  %6s MB  c = %s\n' "$run" "$file" "$wall" "$rss" "$c"
        rm -f "$log" "$log.out"
    done
done
