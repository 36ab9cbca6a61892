#!/usr/bin/env bash
# The steady-state check's share of one `dampid identify` run by wall time (issue 32's "the
# check ≤ 15 % of the run"): perf samples the run at 2 kHz on every thread; the check's
# phase is from its first to its last sample in the check's functions (the records'
# noise, the period fits, the judging; with the measured pipeline no other stage calls
# them). Prints the phase, the run, and the functions most sampled inside the phase.
# Needs `perf`. Not run in CI.
#
#   bash benches/end_to_end/check_phase.sh target/release/dampid /tmp/dampid-one/one_record_measured.toml 3
#
# BASELINE=path/to/old/dampid also runs an older build, interleaved.
set -euo pipefail
bin=${1:?usage: check_phase.sh DAMPID MODEL [RUNS]}
model=${2:?usage: check_phase.sh DAMPID MODEL [RUNS]}
runs=${3:-3}
data=$(mktemp)
trap 'rm -f "$data"' EXIT
phase() {
    perf record -q -F 2000 -o "$data" "$1" identify "$model" >/dev/null 2>&1
    perf script -i "$data" -F tid,time,ip,sym 2>/dev/null | python3 -c '
import collections, sys
rows = []
for line in sys.stdin:
    p = line.split()
    if len(p) >= 4:
        rows.append((float(p[1].rstrip(":")), " ".join(p[3:])))
keys = ("steady_state", "record_noise", "noise_floor", "packed::", "fused_sums::", "WholeSampleDft", "realfft", "rustfft")
inside = [t for t, s in rows if any(k in s for k in keys)]
start, end = min(inside), max(inside)
total = rows[-1][0] - rows[0][0]
within = [s for t, s in rows if start <= t <= end]
print("check phase %4.0f ms of %4.0f ms (%2.0f %%)" % (1e3 * (end - start), 1e3 * total, 100 * (end - start) / total))
for s, c in collections.Counter(within).most_common(5):
    print("    %5.1f %%  %s" % (100 * c / len(within), s[:70]))
'
}
for run in $(seq "$runs"); do
    echo "--- run $run"
    printf 'dampid    '
    phase "$bin"
    if [ -n "${BASELINE:-}" ]; then
        printf 'BASELINE  '
        phase "$BASELINE"
    fi
done
