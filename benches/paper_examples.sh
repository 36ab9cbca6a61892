#!/usr/bin/env bash
# End-to-end time of the paper examples (every case of the paper's sections 2.2 and 3),
# release build, each binary run REPEAT times (default 5); prints the fastest and the
# median run of each and their totals. The examples are built first, so compilation is
# not timed; the time is the binary's wall clock (as with `cargo run --release
# --example NAME`, less cargo's own start-up).
#
#   bash benches/paper_examples.sh
#   REPEAT=10 bash benches/paper_examples.sh
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
target="${CARGO_TARGET_DIR:-target}"

cargo build --release --examples --quiet
echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg); threads: ${RAYON_NUM_THREADS:-$(nproc)}"
python3 - "$target/release/examples" "${REPEAT:-5}" <<'PY'
import statistics
import subprocess
import sys
import time

directory, repeat = sys.argv[1], int(sys.argv[2])
examples = ["paper_four_mass", "paper_four_mass_pod", "paper_harmonic", "paper_string"]
print("| example | fastest s | median s |")
print("|---|---|---|")
totals = [0.0, 0.0]
for example in examples:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run([f"{directory}/{example}"], check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    fastest, median = min(times), statistics.median(times)
    totals[0] += fastest
    totals[1] += median
    print(f"| {example} | {fastest:.3f} | {median:.3f} |")
print(f"| **total** | **{totals[0]:.3f}** | **{totals[1]:.3f}** |")
PY
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
