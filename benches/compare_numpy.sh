#!/usr/bin/env bash
# Regressor building: the NumPy baseline (../shared/baselines/regressor_numpy.py) against
# our criterion bench (benches/regressor.rs), in one sitting, at 1 and 2 threads.
#
#   bash benches/compare_numpy.sh            # from any directory
#   THREADS="1" bash benches/compare_numpy.sh
#
# NumPy column: the baseline's build_row_seconds_min (best of its 3 repeats).
# dampid column: criterion's MEDIAN point estimate (<target>/criterion/build_row/
#   t{T}/n{n}_N{N}/new/estimates.json), robust to the odd slow sample when other builds
#   share the machine. Best-of-3 against a median favours NumPy slightly.
# ratio = NumPy / dampid (above 1: dampid is faster). The last two columns put
#   criterion's fastest sample (new/sample.json) against the NumPy best of 3: the
#   like-for-like comparison when the machine is shared.
#
# Sizes are those of the bench (n DOFs x N samples); n=1000, N=1e5 is the baseline's
# default. Installs numpy and scipy for the baseline when they are missing.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

baseline="../shared/baselines/regressor_numpy.py"
threads_list="${THREADS:-1 2}"
sizes=("1000 100000" "100 100000" "1000 10000")
target="${CARGO_TARGET_DIR:-target}"
criterion_home="${CRITERION_HOME:-$target/criterion}"
out="$target/compare_numpy"
mkdir -p "$out"

if [[ ! -f "$baseline" ]]; then
    echo "baseline not found: $repo/$baseline" >&2
    exit 1
fi
if ! python3 -c 'import numpy, scipy' 2>/dev/null; then
    echo "installing numpy and scipy for the baseline" >&2
    python3 -m pip install --quiet numpy scipy
fi

echo "== machine"
echo "cores: $(nproc); cpu: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)"
echo "memory: $(free -g | awk '/^Mem:/ {print $2 " GiB"}'); load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "numpy: $(python3 -c 'import numpy; print(numpy.__version__)'); $(rustc --version)"
if commit="$(git rev-parse --short HEAD 2>/dev/null)"; then
    [[ -z "$(git status --porcelain 2>/dev/null)" ]] || commit="$commit + uncommitted changes"
    echo "dampid: $commit"
fi

# Build first so compilation is not mixed with the timings below.
cargo bench --bench regressor --no-run

marker="$out/.started"
touch "$marker"

for t in $threads_list; do
    for size in "${sizes[@]}"; do
        read -r n samples <<<"$size"
        echo "== NumPy baseline: n=$n N=$samples threads=$t"
        OMP_NUM_THREADS="$t" OPENBLAS_NUM_THREADS="$t" MKL_NUM_THREADS="$t" \
            python3 "$baseline" --dofs "$n" --samples "$samples" --threads "$t" \
            --json "$out/numpy_n${n}_N${samples}_t${t}.json" >/dev/null
    done
    echo "== dampid (criterion): RAYON_NUM_THREADS=$t"
    RAYON_NUM_THREADS="$t" cargo bench --bench regressor -- "build_row/t${t}/"
done

echo "== load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
python3 - "$out" "$criterion_home" "$marker" "$threads_list" "${sizes[@]}" <<'EOF'
import json
import os
import sys

out, criterion_home, marker = sys.argv[1], sys.argv[2], sys.argv[3]
threads = sys.argv[4].split()
sizes = [tuple(int(x) for x in s.split()) for s in sys.argv[5:]]
started = os.path.getmtime(marker)

print("| size (n x N) | threads | NumPy s (min of 3) | dampid s (criterion median) "
      "| NumPy / dampid | dampid s (fastest sample) | NumPy / dampid, best vs best |")
print("|---|---|---|---|---|---|---|")
for n, samples in sizes:
    for t in threads:
        with open(f"{out}/numpy_n{n}_N{samples}_t{t}.json") as f:
            numpy_s = json.load(f)["build_row_seconds_min"]
        path = f"{criterion_home}/build_row/t{t}/n{n}_N{samples}/new/estimates.json"
        if os.path.getmtime(path) < started:
            sys.exit(f"{path} is older than this run: did the bench run?")
        with open(path) as f:
            dampid_s = json.load(f)["median"]["point_estimate"] * 1e-9
        with open(path.replace("estimates.json", "sample.json")) as f:
            sample = json.load(f)
        best_s = min(t_ns / i for t_ns, i in zip(sample["times"], sample["iters"])) * 1e-9
        print(f"| {n} x {samples} | {t} | {numpy_s:.4f} | {dampid_s:.4f} | {numpy_s / dampid_s:.2f} "
              f"| {best_s:.4f} | {numpy_s / best_s:.2f} |")
EOF
