#!/usr/bin/env bash
# The one-record case of issue 32 (BENCHMARKS §7): record_1 of generate.py alone (100 DOFs
# × 2·10⁵ samples, x, v, f, t uncompressed, 323 MB), 201 coefficients (one per chain and
# ground dashpot), windows of one period, accept_transient = true; `dampid identify` with
# measured velocities and with the default pipeline, against numpy.load of every array
# timed in-process (best of several, in the same sitting). Not run in CI.
#
#   cargo build --release --bin dampid
#   bash benches/end_to_end/one_record.sh [DATA_DIR] [REPEATS]
#
# BASELINE=path/to/old/dampid also times an older build, interleaved (before/after).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${1:-/tmp/dampid-one}
repeats=${2:-3}
venv=${VENV:-/tmp/dampid-end-to-end-venv}
bin=${CARGO_TARGET_DIR:-$root/target}/release/dampid
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet numpy scipy
fi
py=$venv/bin/python
[ -f "$data/one_record_measured.toml" ] || "$py" "$here/generate.py" "$data" --one
[ -x "$bin" ] || { echo "build first: cargo build --release --bin dampid" >&2; exit 1; }
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); $(git -C "$root" rev-parse --short HEAD)"
"$py" "$here/numpy_pipeline.py" "$data" --load --one --repeats 5
timed() {
    local label=$1
    shift
    local log
    log=$(mktemp)
    /usr/bin/time -f "%e %U %S %M" -o "$log" "$@" >/dev/null
    read -r wall user sys rss <"$log"
    printf '%-34s %6.2f s wall  %6.2f s user  %5.2f s sys  %5.0f MB\n' "$label" "$wall" "$user" "$sys" "$((rss / 1024))"
    rm -f "$log"
}
# With BASELINE, the two builds take turns going first: a run that follows a default run
# (whose exit leaves the VM's memory to be zeroed and compacted again) pays up to 0.7 s
# of system time more, so a fixed order would charge it to one build.
for run in $(seq "$repeats"); do
    echo "--- run $run"
    for velocity in measured harmonic_projection; do
        model=$data/one_record_$velocity.toml
        if [ -n "${BASELINE:-}" ] && [ $((run % 2)) -eq 0 ]; then
            timed "BASELINE $velocity" "$BASELINE" identify "$model" --json
            timed "dampid $velocity" "$bin" identify "$model" --json
        else
            timed "dampid $velocity" "$bin" identify "$model" --json
            if [ -n "${BASELINE:-}" ]; then
                timed "BASELINE $velocity" "$BASELINE" identify "$model" --json
            fi
        fi
    done
done
"$py" "$here/numpy_pipeline.py" "$data" --load --one --repeats 5
