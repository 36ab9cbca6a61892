#!/usr/bin/env bash
# The steady-state check's share of one `dampid identify` run by instructions (issue 32's
# "the check ≤ 15 % of the run"), which neither the machine's load nor this VM's page
# zeroing moves: `valgrind --tool=callgrind` on one thread, the check being the inclusive
# cost of its entry points on rayon's worker (the records' noise `RecordNoise::of`, the
# spans' tasks `project_task`: period fits and span residuals, the judging `check_window`)
# and of `check_with` itself on the main thread (its serial part: the spans' plan, the report,
# the drops); none calls another. In the default run the records' noise is also the
# rows': the check estimates it for both. Callgrind runs AVX2 code where the CPU has AVX-512,
# so the instruction mix is not the machine's; wall time is `check_phase.sh`'s and
# `one_record.sh`'s. Takes 3–4 minutes per run on the 323 MB record (a build with line tables,
# `CARGO_PROFILE_RELEASE_DEBUG=line-tables-only`, names each function with its file: read too). Not run in CI.
#
#   bash benches/end_to_end/check_instructions.sh target/release/dampid /tmp/dampid-one/one_record_measured.toml
set -euo pipefail
bin=$(realpath "${1:?usage: check_instructions.sh DAMPID MODEL}")
model=$(realpath "${2:?usage: check_instructions.sh DAMPID MODEL}")
out=$(mktemp)
trap 'rm -f "$out"' EXIT
(cd "$(dirname "$model")" && RAYON_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$out" \
    "$bin" identify "$model" >/dev/null 2>&1)
callgrind_annotate --inclusive=yes --threshold=100 "$out" 2>/dev/null | python3 -c '
import re, sys
parts = ("fourier::noise_floor::select_with_spectrum", "fourier::record_noise::RecordNoise::of", "steady_state::spans::project_task",
         "steady_state::judge::check_window", "steady_state::check_with")
total, found = None, {}
for line in sys.stdin:
    if "PROGRAM TOTALS" in line:
        total = int(line.split()[0].replace(",", ""))
    m = re.match(r"\s*([\d,]+) .*\S*:dampid::prep::(\S+) ", line)
    if m and m.group(2) in parts:
        found.setdefault(m.group(2), int(m.group(1).replace(",", "")))
check = sum(found.values())
print("run    %.3e instructions" % total)
for name in parts:
    print("  %-30s %.3e" % (name, found.get(name, 0)))
print("check  %.3e instructions, %.1f %% of the run" % (check, 100 * check / total))
'
