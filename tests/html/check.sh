#!/usr/bin/env bash
# Renders the HTML reports of three shipped models in headless Chromium and checks them
# as a reader sees them (tests/html/checks.js measures, check.py judges): no console
# errors, nothing wider than the viewport, every SVG text at least 12 px as shown, a
# legend in every plot, and "not determined" on the walkthrough's first try; two
# variable-projection pages besides. Installs
# Debian's chromium when it is missing. With SCREENSHOTS=1 it also refreshes
# docs/screenshots/.
#
# Usage: tests/html/check.sh            (uses target/release/dampid, built if missing)
set -euo pipefail
cd "$(dirname "$0")/../.."
dampid="${CARGO_TARGET_DIR:-target}/release/dampid"
if [ ! -x "$dampid" ]; then
    cargo build --release --bin dampid
fi
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
    echo "installing Debian's chromium"
    sudo=""
    [ "$(id -u)" = "0" ] || sudo="sudo"
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y chromium
    browser=$(command -v chromium)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
       --disable-background-networking --disable-component-update --disable-sync
       --hide-scrollbars --force-device-scale-factor=1)
status=0
check() {
    local name=$1 model=$2 extra=${3:-}
    "$dampid" identify "$model" --report "$work/$name" >/dev/null
    check_page "$name" "$extra"
}
# Checks $work/NAME/report.html, however it was made.
check_page() {
    local name=$1 extra=${2:-}
    local page="$work/$name/report.html"
    # A copy with the checks injected first in <head>; the report itself stays script-free.
    python3 - "$page" "$work/$name/checked.html" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
script = open("tests/html/checks.js", encoding="utf-8").read()
open(sys.argv[2], "w", encoding="utf-8").write(page.replace("<head>", "<head><script>" + script + "</script>", 1))
PY
    "$browser" "${flags[@]}" --user-data-dir="$(mktemp -d -p "$work")" --window-size=1280,900 \
        --virtual-time-budget=5000 --dump-dom "file://$work/$name/checked.html" \
        >"$work/$name/dom.html" 2>"$work/$name/chromium.log" || true
    if ! python3 tests/html/check.py "$work/$name/dom.html" "$name" $extra; then
        status=1
    fi
    if [ "${SCREENSHOTS:-0}" = "1" ]; then
        "$browser" "${flags[@]}" --user-data-dir="$(mktemp -d -p "$work")" --window-size=1280,2600 \
            --screenshot="$PWD/docs/screenshots/$name.png" "file://$page" \
            >/dev/null 2>&1 || true
        echo "  screenshot docs/screenshots/$name.png"
    fi
}
check walkthrough_first_try models/walkthrough_first_try.toml --not-determined
check walkthrough models/walkthrough.toml
check four_mass_pod models/four_mass_pod.toml
# Variable projection: a stepped-sine table with estimated residual receptances (joint
# intervals, energy per cycle, equivalent damping) and records with an estimated exponent
# (profile interval).
check bolted_joint_residual models/bolted_joint_stepped_sine_residual.toml
check four_mass_power models/four_mass_power.toml
# The Python package's page of records from NumPy arrays (steady-state table and
# provenance as the CLI's), when a Python with the package is at hand: $PYTHON, or the
# virtual environment .ci/run makes.
python=${PYTHON:-.venv-ci/bin/python}
if [ -x "$python" ] && "$python" -c "import dampid" 2>/dev/null; then
    mkdir -p "$work/python_arrays"
    "$python" - "$work/python_arrays/report.html" <<'PY'
import sys
sys.path.insert(0, "examples/python")
import chain, dampid
t, x, v, f = chain.simulate([0.25, 0.5, 0.75, 1.0], [chain.OMEGA] * 4)
records = [dampid.Record(x=x[k], t=t, forces=[(f[k], 4)], frequency=chain.OMEGA, label=f"a{k}") for k in range(4)]
dampid.identify(dampid.Model.from_toml(chain.MODEL), records).write_html(sys.argv[1])
PY
    check_page python_arrays
else
    echo "python_arrays: skipped (no Python with the dampid package; set PYTHON)"
fi
exit $status
