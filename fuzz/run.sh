#!/usr/bin/env bash
# Runs dampid's fuzz targets one after another, each for SECONDS (default 60) or RUNS
# executions, whichever comes first. Needs cargo-fuzz (`cargo install cargo-fuzz`);
# RUSTC_BOOTSTRAP=1 lets the stable toolchain accept the nightly flags libFuzzer builds
# use. New inputs go to fuzz/corpus/TARGET (not committed); fuzz/seeds/TARGET is the
# committed seed corpus. A crash stops the run and is saved under fuzz/artifacts/TARGET.
#
#   fuzz/run.sh [SECONDS] [TARGET...]
#   RUNS=1000000 fuzz/run.sh 600          # the full run of docs/robustness.md
#   SANITIZER=none fuzz/run.sh 5          # no AddressSanitizer (faster, and works
#                                         # where the ASan runtime is missing)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
shift || true
if [ $# -gt 0 ]; then
    targets=("$@")
else
    targets=(model_file expression csv_table identify npy npz mat uff job)
fi
export RUSTC_BOOTSTRAP=1
for target in "${targets[@]}"; do
    echo "== fuzz $target: ${seconds}s, runs ${RUNS:--1}"
    mkdir -p "fuzz/corpus/$target"
    cargo fuzz run --sanitizer "${SANITIZER:-address}" "$target" \
        "fuzz/corpus/$target" "fuzz/seeds/$target" -- \
        -max_total_time="$seconds" -runs="${RUNS:--1}" -timeout=30 \
        -rss_limit_mb=4096 -print_final_stats=1
done
