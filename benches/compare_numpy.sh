#!/usr/bin/env bash
# dampid against the NumPy baseline (../shared/baselines/regressor_numpy.py), in one sitting:
#
#   1. the machine's roof: a streaming read over 1 GiB (benches/bandwidth.rs) at each
#      thread count;
#   2. regressor building (benches/regressor.rs) against the baseline's build_row, at
#      1 and 2 threads, with dampid's effective bandwidth (bytes of V / time) as a
#      fraction of the roof measured in step 1, and the instruction set of dampid's
#      loops (the bench's "simd: avx512|avx2|baseline" line; DAMPID_SIMD=avx2 forces a
#      level the CPU has);
#   3. the nonnegative fit with 2001 coefficients and 4002 equations
#      (benches/fit.rs, constrained_fit/interior/p2001) against the baseline's scipy
#      NNLS (--solve --dofs 1000), with both errors max |θ̂ − θ|.
#
#   bash benches/compare_numpy.sh            # from any directory
#   THREADS="1" SKIP_FIT=1 bash benches/compare_numpy.sh
#
# NumPy column: the baseline's build_row_seconds_min (best of its 3 repeats).
# dampid column: criterion's MEDIAN point estimate (<target>/criterion/build_row/
#   t{T}/n{n}_N{N}/new/estimates.json), robust to the odd slow sample when other builds
#   share the machine. Best-of-3 against a median favours NumPy slightly.
# ratio = NumPy / dampid (above 1: dampid is faster). The "best vs best" columns put
#   criterion's fastest sample (new/sample.json) against the NumPy best of 3: the
#   like-for-like comparison when the machine is shared. The bandwidth fractions use
#   the fastest samples of both benches too.
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
echo "numpy: $(python3 -c 'import numpy; print(numpy.__version__)'); scipy: $(python3 -c 'import scipy; print(scipy.__version__)'); $(rustc --version)"
if commit="$(git rev-parse --short HEAD 2>/dev/null)"; then
    [[ -z "$(git status --porcelain 2>/dev/null)" ]] || commit="$commit + uncommitted changes"
    echo "dampid: $commit"
fi

# Build first so compilation is not mixed with the timings below.
cargo bench --bench regressor --bench bandwidth --bench fit --no-run

marker="$out/.started"
touch "$marker"

for t in $threads_list; do
    echo "== streaming-read roof (criterion): RAYON_NUM_THREADS=$t"
    RAYON_NUM_THREADS="$t" cargo bench --bench bandwidth -- "stream_read/t${t}/"
    for size in "${sizes[@]}"; do
        read -r n samples <<<"$size"
        echo "== NumPy baseline: n=$n N=$samples threads=$t"
        OMP_NUM_THREADS="$t" OPENBLAS_NUM_THREADS="$t" MKL_NUM_THREADS="$t" \
            python3 "$baseline" --dofs "$n" --samples "$samples" --threads "$t" \
            --json "$out/numpy_n${n}_N${samples}_t${t}.json" >/dev/null
    done
    echo "== dampid (criterion): RAYON_NUM_THREADS=$t"
    RAYON_NUM_THREADS="$t" cargo bench --bench regressor -- "build_row/t${t}/" | tee "$out/regressor_t${t}.log"
done

if [[ -z "${SKIP_FIT:-}" ]]; then
    echo "== NumPy baseline: --solve --dofs 1000 (scipy NNLS, 4002 x 2001)"
    # --samples 1000 keeps the (untimed here) regressor part short; the solve's size
    # depends only on --dofs.
    python3 "$baseline" --solve --dofs 1000 --samples 1000 --repeat 1 \
        --json "$out/numpy_solve_dofs1000.json" >/dev/null
    echo "== dampid (criterion): constrained_fit/interior/p2001"
    DAMPID_FIT_ERRORS="$out/fit_errors.json" \
        cargo bench --bench fit -- "constrained_fit/interior/p2001"
fi

echo "== load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
python3 - "$out" "$criterion_home" "$marker" "$threads_list" "${SKIP_FIT:-}" "${sizes[@]}" <<'PY'
import json
import os
import sys

out, criterion_home, marker = sys.argv[1], sys.argv[2], sys.argv[3]
threads = sys.argv[4].split()
skip_fit = bool(sys.argv[5])
sizes = [tuple(int(x) for x in s.split()) for s in sys.argv[6:]]
started = os.path.getmtime(marker)


def criterion(*parts):
    """(median s, fastest sample s) of a criterion benchmark run in this sitting."""
    path = os.path.join(criterion_home, *parts, "new", "estimates.json")
    if os.path.getmtime(path) < started:
        sys.exit(f"{path} is older than this run: did the bench run?")
    with open(path) as f:
        median = json.load(f)["median"]["point_estimate"] * 1e-9
    with open(path.replace("estimates.json", "sample.json")) as f:
        sample = json.load(f)
    best = min(t / i for t, i in zip(sample["times"], sample["iters"])) * 1e-9
    return median, best


simd = {}
for t in threads:
    with open(f"{out}/regressor_t{t}.log") as f:
        simd[t] = next((line.split()[1] for line in f if line.startswith("simd: ")), "?")

roof = {}
print("| threads | streaming read, GB/s (median) | streaming read, GB/s (fastest) |")
print("|---|---|---|")
for t in threads:
    median, best = criterion("stream_read", f"t{t}", "1GiB")
    roof[t] = 2**30 / best / 1e9
    print(f"| {t} | {2**30 / median / 1e9:.2f} | {roof[t]:.2f} |")
print()
print("| size (n x N) | threads | NumPy s (min of 3) | dampid s (criterion median) "
      "| NumPy / dampid | dampid s (fastest sample) | NumPy / dampid, best vs best "
      "| dampid GB/s of V (fastest) | fraction of streaming read | simd |")
print("|---|---|---|---|---|---|---|---|---|---|")
for n, samples in sizes:
    for t in threads:
        with open(f"{out}/numpy_n{n}_N{samples}_t{t}.json") as f:
            numpy_s = json.load(f)["build_row_seconds_min"]
        median, best = criterion("build_row", f"t{t}", f"n{n}_N{samples}")
        gbps = 8 * n * samples / best / 1e9
        print(f"| {n} x {samples} | {t} | {numpy_s:.4f} | {median:.4f} | {numpy_s / median:.2f} "
              f"| {best:.4f} | {numpy_s / best:.2f} | {gbps:.2f} | {gbps / roof[t]:.0%} | {simd[t]} |")

if not skip_fit:
    with open(f"{out}/numpy_solve_dofs1000.json") as f:
        solve = json.load(f)
    with open(f"{out}/fit_errors.json") as f:
        errors = json.load(f)
    median, best = criterion("constrained_fit", "interior", "p2001")
    print()
    print("| nonnegative fit, 4002 x 2001 | seconds | max abs error |")
    print("|---|---|---|")
    print(f"| scipy NNLS (baseline) | {solve['nnls_seconds']:.3f} | {solve['nnls_max_abs_err']:.2e} |")
    print(f"| dampid fit::constrained (criterion median) | {median:.3f} | {errors['interior/p2001']:.2e} |")
    print(f"| dampid fit::constrained (fastest sample) | {best:.3f} | |")
    print(f"| NNLS / dampid (median; fastest) | {solve['nnls_seconds'] / median:.1f}; "
          f"{solve['nnls_seconds'] / best:.1f} | |")
PY
