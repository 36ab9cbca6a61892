#!/usr/bin/env bash
# End-to-end benchmark (issue 17): `dampid identify` on 4 records of 100 DOFs × 2·10⁵
# samples (1.29 GB of .npz, whole samples per period) for the three velocity sources,
# with wall time and peak memory (/usr/bin/time -v, maximum resident set size), and in
# the same run the NumPy/SciPy pipeline (numpy_pipeline.py) and numpy.load alone (timed
# in-process, best of several reads, every array read fully). The one-record case of
# issue 32 (201 coefficients, one-period windows) is one_record.sh.
# Not run in CI (too big).
#
#   cargo build --release --bin dampid
#   bash benches/end_to_end/run.sh [DATA_DIR] [REPEATS]
#
# DATA_DIR (default /tmp/dampid-end-to-end) receives the data, made once by generate.py;
# the Python deps (numpy, scipy) go into a venv it creates ($VENV, default
# /tmp/dampid-end-to-end-venv). Each timing is repeated REPEATS times (default 3) and
# every run is printed; the page cache is warm after the first read of each file.
# BASELINE=path/to/old/dampid also times an older build on the default pipeline, in
# the same runs (before/after).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${1:-/tmp/dampid-end-to-end}
repeats=${2:-3}
venv=${VENV:-/tmp/dampid-end-to-end-venv}
bin=${CARGO_TARGET_DIR:-$root/target}/release/dampid

if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet numpy scipy
fi
py=$venv/bin/python
if [ ! -f "$data/record_4.npz" ]; then
    echo "generating $data ..."
    "$py" "$here/generate.py" "$data"
fi
[ -x "$bin" ] || { echo "build first: cargo build --release --bin dampid" >&2; exit 1; }

echo "data: $(du -cb "$data"/record_*.npz | tail -1 | cut -f1) bytes in $data"
echo "machine: $(nproc) cores; $(git -C "$root" rev-parse --short HEAD); $("$py" -c 'import numpy, scipy; print("numpy", numpy.__version__, "scipy", scipy.__version__)')"

# timed LABEL COMMAND...: wall seconds and peak RSS (MB) of one run
timed() {
    local label=$1
    shift
    local log
    log=$(mktemp)
    /usr/bin/time -v "$@" >"$log.out" 2>"$log" || { cat "$log" "$log.out" >&2; exit 1; }
    local wall rss
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$log" | awk -F: '{ if (NF == 3) print $1*3600 + $2*60 + $3; else print $1*60 + $2 }')
    rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$log")
    printf '%-42s %8.2f s %8s MB\n' "$label" "$wall" "$rss"
    cp "$log.out" "/tmp/dampid-end-to-end-last-$(echo "$label" | tr ' /=' '___').out"
    rm -f "$log" "$log.out"
}

for run in $(seq "$repeats"); do
    echo "--- run $run"
    # numpy.load in-process, best of 3 reads of every array (no interpreter start-up)
    "$py" "$here/numpy_pipeline.py" "$data" --load --repeats 3
    for velocity in measured central_difference harmonic_projection; do
        timed "dampid identify velocity=$velocity" "$bin" identify "$data/chain100_$velocity.toml" --json
    done
    if [ -n "${BASELINE:-}" ]; then
        timed "BASELINE identify velocity=harmonic_projection" "$BASELINE" identify "$data/chain100_harmonic_projection.toml" --json
    fi
    timed "numpy/scipy pipeline (FFT projection)" "$py" "$here/numpy_pipeline.py" "$data"
done
echo "--- last outputs"
for f in /tmp/dampid-end-to-end-last-*.out; do
    echo "$f:"
    grep -E 'c_chain|c_ground|total|load|projection|lstsq' "$f" | head -12
done
