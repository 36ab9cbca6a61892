#!/usr/bin/env bash
# The steady-state check's share of one `dampid identify` run by instructions (issue 32's
# "the check ≤ 15 % of the run"), which neither the machine's load nor this VM's page
# zeroing moves: `valgrind --tool=callgrind` on one thread, the check being the inclusive
# cost of its four entry points (the spans' noise floor and residual `fit_span_from`, the
# periods' transforms `period_spectrum`, the periods' fits `fit_period_from`, the judging
# `check_window`; none calls another). Callgrind runs AVX2 code where the CPU has AVX-512,
# so the instruction mix is not the machine's; wall time is `check_phase.sh`'s and
# `one_record.sh`'s. Takes 3–4 minutes per run on the 323 MB record. Not run in CI.
#
#   bash benches/end_to_end/check_instructions.sh target/release/dampid /tmp/dampid-one/one_record_measured.toml
set -euo pipefail
bin=$(realpath "${1:?usage: check_instructions.sh DAMPID MODEL}")
model=$(realpath "${2:?usage: check_instructions.sh DAMPID MODEL}")
out=$(mktemp)
trap 'rm -f "$out"' EXIT
(cd "$(dirname "$model")" && RAYON_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$out" \
    "$bin" identify "$model" >/dev/null 2>&1)
callgrind_annotate --inclusive=yes "$out" 2>/dev/null | python3 -c '
import re, sys
parts = ("projection::fit_span_from", "projection::period_spectrum",
         "projection::fit_period_from", "judge::check_window")
total, found = None, {}
for line in sys.stdin:
    if "PROGRAM TOTALS" in line:
        total = int(line.split()[0].replace(",", ""))
    m = re.match(r"\s*([\d,]+) .*\?\?\?:dampid::prep::steady_state::(\S+) ", line)
    if m and m.group(2) in parts:
        found.setdefault(m.group(2), int(m.group(1).replace(",", "")))
check = sum(found.values())
print("run    %.3e instructions" % total)
for name in parts:
    print("  %-30s %.3e" % (name, found.get(name, 0)))
print("check  %.3e instructions, %.1f %% of the run" % (check, 100 * check / total))
'
