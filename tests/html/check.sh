#!/usr/bin/env bash
# Renders the HTML reports of shipped models in headless Chromium and checks them
# as a reader sees them (tests/html/checks.js measures, check.py judges): no console
# errors, nothing wider than the viewport, every SVG text at least 12 px as shown, a
# legend in every plot, and "not determined" on the walkthrough's first try; two
# variable-projection pages besides, a hammer ringdown's backbone, a ringdown's and a
# stepped sine's backbones side by side (dampid backbones), and the page of a 12-sweep, 41-point-per-sweep
# stepped-sine table (made by the bolted-joint generator): under 8,000 px tall at
# 1200 px wide, its sweeps named, the table file's SHA-256 listed, the ζ_eq(X) plot
# shown. Installs Debian's chromium when it is missing. With SCREENSHOTS=1 it also
# refreshes docs/screenshots/.
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
    local name=$1 model=$2
    shift 2
    "$dampid" identify "$model" --report "$work/$name" >/dev/null
    check_page "$name" "$@"
}
# Checks $work/NAME/report.html, however it was made, at $WIDTH px (default 1280); the
# arguments after NAME go to check.py.
check_page() {
    local name=$1
    shift
    local page="$work/$name/report.html" width=${WIDTH:-1280}
    # A copy with the checks injected first in <head>; the report itself stays script-free.
    python3 - "$page" "$work/$name/checked.html" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
script = open("tests/html/checks.js", encoding="utf-8").read()
open(sys.argv[2], "w", encoding="utf-8").write(page.replace("<head>", "<head><script>" + script + "</script>", 1))
PY
    "$browser" "${flags[@]}" --user-data-dir="$(mktemp -d -p "$work")" --window-size="$width,900" \
        --virtual-time-budget=5000 --dump-dom "file://$work/$name/checked.html" \
        >"$work/$name/dom.html" 2>"$work/$name/chromium.log" || true
    if ! python3 tests/html/check.py "$work/$name/dom.html" "$name" "$@"; then
        status=1
    fi
    if [ "${SCREENSHOTS:-0}" = "1" ]; then
        screenshot "$name" "$page"
    fi
}
# screenshot NAME PAGE [SUFFIX]: docs/screenshots/NAME[SUFFIX].png, the top 2600 px of
# PAGE at $WIDTH px.
screenshot() {
    local file="docs/screenshots/$1${3:-}.png"
    "$browser" "${flags[@]}" --user-data-dir="$(mktemp -d -p "$work")" --window-size="${WIDTH:-1280},2600" \
        --screenshot="$PWD/$file" "file://$2" >/dev/null 2>&1 || true
    echo "  screenshot $file"
}
check walkthrough_first_try models/walkthrough_first_try.toml --not-determined
check walkthrough models/walkthrough.toml
check four_mass_pod models/four_mass_pod.toml
# Variable projection: a stepped-sine table with estimated residual receptances (joint
# intervals, energy per cycle, equivalent damping) and records with an estimated exponent
# (profile interval).
check bolted_joint_residual models/bolted_joint_stepped_sine_residual.toml
check four_mass_power models/four_mass_power.toml
# A hammer ringdown (free decay): the backbone ζ(X), f(X) and the decay envelope.
check ringdown models/ringdown.toml --expect "<h2>Free decay: backbone</h2>" \
    --expect-plot "Equivalent viscous damping ratio ζ_eq(X)" \
    --expect-plot "Backbone frequency f(X)" --expect-plot "Decay envelope X(t)"
if [ "${SCREENSHOTS:-0}" = "1" ]; then
    python3 - "$work/ringdown/report.html" "$work/ringdown/backbone.html" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
start = page.index("<h2>Free decay: backbone</h2>")
end = page.index("<h2>Provenance</h2>")
open(sys.argv[2], "w", encoding="utf-8").write(page[: page.index("</h1>") + 5] + page[start:end] + "</body></html>")
PY
    WIDTH=1200 screenshot ringdown "$work/ringdown/backbone.html" _backbone
fi
# Backbones of one mode from a ringdown and a stepped sine on one page (dampid backbones).
mkdir -p "$work/backbones"
"$dampid" backbones models/backbones_ringdown.toml models/backbones_stepped.toml \
    --report "$work/backbones" >/dev/null
mv "$work/backbones/backbones.html" "$work/backbones/report.html"
check_page backbones --expect "<h2>Fitted ζ against the first job's</h2>" \
    --expect-plot "Damping ratio ζ(X) of each job" --expect-plot "Frequency f(X) of each job"
if [ "${SCREENSHOTS:-0}" = "1" ]; then
    WIDTH=1200 screenshot backbones "$work/backbones/report.html"
fi
# A 12-sweep, 41-point-per-sweep table from the bolted-joint generator: the page is
# organised by sweep (under 8,000 px tall at 1200 px wide), names the sweeps, lists the
# table file with its SHA-256 and shows ζ_eq(X).
mkdir -p "$work/table12"
python3 models/data/bolted_joint/generate.py --levels 12 --points 41 --output "$work/table12/table12.csv"
sed -e 's#^file = .*#file = "table12.csv"#' \
    -e 's#^title = .*#title = "Bolted joint, 12 sweeps of 41 points (simulated)"#' \
    models/bolted_joint_stepped_sine.toml >"$work/table12/table12.toml"
sha=$(sha256sum "$work/table12/table12.csv" | cut -d' ' -f1)
WIDTH=1200 check sweeps12 "$work/table12/table12.toml" --max-height 8000 \
    --expect "492 points from 12 sweeps" --expect "<h2>Sweeps</h2>" --expect "level = 12" \
    --expect "$sha" --expect-plot "Equivalent viscous damping ratio ζ_eq(X)" \
    --absent "No data files" --absent "per window" --absent "equation (window)"
if [ "${SCREENSHOTS:-0}" = "1" ]; then
    # The page's energy per cycle and equivalent damping alone (its head, title and the
    # sections from "Dissipated energy per cycle" to the provenance).
    python3 - "$work/sweeps12/report.html" "$work/sweeps12/equivalent.html" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
start = page.index("<h2>Dissipated energy per cycle</h2>")
end = page.index("<h2>Provenance</h2>")
open(sys.argv[2], "w", encoding="utf-8").write(page[: page.index("</h1>") + 5] + page[start:end] + "</body></html>")
PY
    WIDTH=1200 screenshot sweeps12 "$work/sweeps12/equivalent.html" _equivalent
fi
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
