#!/usr/bin/env bash
# Free decay end to end (issue 31's speed target: a 65,536-sample ringdown in under
# 0.2 s): `dampid identify` on the shipped hammer test (models/ringdown.toml: file read,
# mode isolation, 398 cycles, the exponent estimated by variable projection with its
# profile interval, the backbone), the same with the exponent fixed, and the SciPy anchor
# (benches/free_decay/scipy_backbone.py, in-process, best of 7) in the same sitting; and
# the same hammer test read by three accelerometers (benches/free_decay/three_sensors.py:
# 65,536 samples × 3 channels) through the modal filter, with the given mode shape and
# with the record's POD, exponent estimated.
#
# Usage: benches/free_decay/run.sh      (needs a Python with NumPy and SciPy: $PYTHON)
set -euo pipefail
cd "$(dirname "$0")/../.."
dampid="${CARGO_TARGET_DIR:-target}/release/dampid"
[ -x "$dampid" ] || cargo build --release --bin dampid
python=${PYTHON:-python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's#exponent = { estimate = true, initial = 2.0, lower = 1.05, upper = 3.0 }#exponent = 1.5#' \
    -e 's#"data/ringdown/#"'"$PWD"'/models/data/ringdown/#' models/ringdown.toml >"$work/fixed.toml"
best() {
    local best=999
    for _ in 1 2 3 4 5 6 7; do
        local t0 t1
        t0=$(date +%s.%N)
        "$dampid" identify "$1" --json >/dev/null
        t1=$(date +%s.%N)
        best=$(python3 -c "print(min($best, $t1 - $t0))")
    done
    printf '%s: best of 7 %.1f ms\n' "$2" "$(python3 -c "print($best * 1e3)")"
}
uptime
best models/ringdown.toml "dampid identify, exponent estimated (whole process)"
best "$work/fixed.toml" "dampid identify, exponent fixed (whole process)"
"$python" benches/free_decay/three_sensors.py "$work"
best "$work/sensors.toml" "dampid identify, 3 sensors, mode_shape, exponent estimated (whole process)"
best "$work/sensors_pod.toml" "dampid identify, 3 sensors, POD, exponent estimated (whole process)"
"$python" benches/free_decay/scipy_backbone.py
