#!/usr/bin/env bash
# Writes every user-visible output of dampid into one folder, to compare two builds bit
# for bit (tests/snapshots/compare.py): for each models/*.toml the JSON and text report
# of `identify` (and with --bootstrap 200), `check`, an HTML report; `compare`,
# `design`, `reference`, `pod`, `simulate`; and every example that prints a result.
# Each command's stdout, stderr and exit code are kept.
#
#   cargo build --release --bins --examples
#   bash tests/snapshots/snapshot.sh /tmp/before      # on the old commit
#   bash tests/snapshots/snapshot.sh /tmp/after       # on the new one
#   python3 tests/snapshots/compare.py /tmp/before /tmp/after
#
# RAYON_NUM_THREADS is fixed (2 unless set) so that both runs use the same reductions.
set -uo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: snapshot.sh OUT_DIR}
target=${CARGO_TARGET_DIR:-target}/release
bin=$target/dampid
export RAYON_NUM_THREADS=${RAYON_NUM_THREADS:-2}
mkdir -p "$out"

# run NAME COMMAND...: stdout to NAME.out, stderr to NAME.err, exit code to NAME.code.
run() {
    local name=$1
    shift
    "$@" >"$out/$name.out" 2>"$out/$name.err"
    echo $? >"$out/$name.code"
}

for model in models/*.toml; do
    m=$(basename "$model" .toml)
    run "identify_$m.json" "$bin" identify "$model" --json --accept-transient
    run "identify_$m.txt" "$bin" identify "$model" --accept-transient
    run "identify_default_$m.txt" "$bin" identify "$model"
    run "bootstrap_$m.json" "$bin" identify "$model" --json --accept-transient --bootstrap 200
    run "check_$m.txt" "$bin" check "$model" --accept-transient
    run "check_default_$m.txt" "$bin" check "$model"
done
for model in measured_chain four_mass_pod drive_nonperiodic; do
    rm -rf "$out/html_$model"
    run "html_$model" "$bin" identify "models/$model.toml" --accept-transient --report "$out/html_$model"
done
run compare.json "$bin" compare models/measured_chain.toml models/measured_chain_no_friction.toml --json
run compare.txt "$bin" compare models/measured_chain.toml models/measured_chain_no_friction.toml
run compare_drive.txt "$bin" compare models/drive_nonperiodic.toml models/drive_nonperiodic.toml
run design_rayleigh.json "$bin" design models/rayleigh_chain6_design.toml --json
run design_per_dashpot.json "$bin" design models/per_dashpot.toml --json
for rule in rectangular trapezoid spectral; do
    run "reference_$rule.json" "$bin" reference four-mass --json --quadrature "$rule"
done
run reference.txt "$bin" reference four-mass
run pod.json "$bin" pod models/data/chain3/record_1.csv models/data/chain3/record_2.csv --prefix x --json
run pod_shared.txt "$bin" pod models/data/chain3/record_1.csv models/data/chain3/record_2.csv --prefix x --shared
rm -rf "$out/simulate"
run simulate "$bin" simulate models/chain3_generator.toml --out "$out/simulate"
for example in paper_four_mass paper_four_mass_pod paper_harmonic paper_string identifiability; do
    run "example_$example.json" "$target/examples/$example" --json
done
for example in per_dashpot noise_robust nonperiodic_drive velocity_comparison; do
    run "example_$example.txt" "$target/examples/$example"
done
echo "wrote $(ls "$out" | wc -l) entries to $out"
