#!/usr/bin/env bash
# Times `dampid identify` on every models/*.toml and the paper examples for two builds
# in one sitting, runs interleaved (A, B, A, B, …) so that both see the same machine,
# and prints the median of each with the ratio B/A. For a restructure that must not
# slow anything down: A is a checkout of the old commit, B this one.
#
#   git worktree add /tmp/old <commit> && (cd /tmp/old && cargo build --release --bins --examples)
#   cargo build --release --bins --examples
#   bash benches/before_after.sh /tmp/old [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: before_after.sh OLD_CHECKOUT [REPEAT]}
repeat=${2:-7}
new_target=${CARGO_TARGET_DIR:-target}/release
old_target=$old/target/release
echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg); threads: ${RAYON_NUM_THREADS:-$(nproc)}"
python3 - "$old_target" "$new_target" "$repeat" "$old" <<'PY'
import glob, os, statistics, subprocess, sys, time

old, new, repeat, old_tree = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
cases = []
for model in sorted(glob.glob("models/*.toml")):
    name = os.path.basename(model)[:-5]
    cases.append((f"identify {name}",
                  [f"{old}/dampid", "identify", os.path.join(old_tree, model), "--json", "--accept-transient"],
                  [f"{new}/dampid", "identify", model, "--json", "--accept-transient"]))
for example in ["paper_four_mass", "paper_four_mass_pod", "paper_harmonic", "paper_string"]:
    cases.append((f"example {example}", [f"{old}/examples/{example}"], [f"{new}/examples/{example}"]))

def run(command):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start

print("| case | before s | after s | after/before |")
print("|---|---|---|---|")
totals = [0.0, 0.0]
for name, a, b in cases:
    ta, tb = [], []
    for _ in range(repeat):
        ta.append(run(a))
        tb.append(run(b))
    ma, mb = statistics.median(ta), statistics.median(tb)
    totals[0] += ma
    totals[1] += mb
    print(f"| {name} | {ma:.3f} | {mb:.3f} | {mb / ma:.3f} |")
print(f"| **total** | **{totals[0]:.3f}** | **{totals[1]:.3f}** | **{totals[1] / totals[0]:.3f}** |")
PY
