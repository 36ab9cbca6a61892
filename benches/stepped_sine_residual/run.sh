#!/bin/sh
# Issue 30 item 6: dampid against a SciPy least_squares baseline on the same 12-sweep ×
# 41-point stepped-sine table (table12.csv; viscous + power law with its exponent and
# one residual receptance per sweep estimated), in the same sitting.
#
#   benches/stepped_sine_residual/run.sh [REPEAT]     (default 3; needs /work/venv or
#                                                      PYTHON with numpy and scipy)
#
# dampid: the whole `dampid identify` process (reading the table, the outer loop, the
# joint covariance, the exponent's profile interval, the report), best wall time of
# REPEAT runs, for model.toml (propagated weighting, the default) and model_ordinary.toml
# (ordinary weighting: the residual vector the SciPy baseline minimises). SciPy: the
# in-process time of least_squares alone (no intervals), best of REPEAT, '2-point' and
# analytic Jacobians. Prints the load average beside the times and the ratios.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
repeat=${1:-3}
python=${PYTHON:-/work/venv/bin/python}
dampid="$root/target/release/dampid"
[ -x "$dampid" ] || (cd "$root" && cargo build --release --bin dampid)
echo "commit $(cd "$root" && git rev-parse --short HEAD); $(uptime)"
best() { # best wall seconds of $repeat runs of dampid identify $1
    b=""
    i=0
    while [ "$i" -lt "$repeat" ]; do
        s=$(date +%s.%N)
        "$dampid" identify "$here/$1" > /dev/null
        e=$(date +%s.%N)
        t=$(echo "$e - $s" | bc -l)
        if [ -z "$b" ] || [ "$(echo "$t < $b" | bc -l)" = 1 ]; then b=$t; fi
        i=$((i + 1))
    done
    printf '%.3f' "$b"
}
prop=$(best model.toml)
ord=$(best model_ordinary.toml)
json=$("$python" "$here/scipy_baseline.py" --repeat "$repeat" --json)
two=$(echo "$json" | "$python" -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["2-point"]["seconds"])')
ana=$(echo "$json" | "$python" -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["analytic"]["seconds"])')
echo "dampid identify, propagated weighting (model.toml):         $prop s"
echo "dampid identify, ordinary weighting (model_ordinary.toml):  $ord s"
echo "scipy least_squares, jac='2-point':                         $two s"
echo "scipy least_squares, analytic jac:                          $ana s"
echo "ratio dampid (ordinary) / scipy 2-point: $(echo "$ord / $two" | bc -l | cut -c1-6)"
echo "ratio dampid (ordinary) / scipy analytic: $(echo "$ord / $ana" | bc -l | cut -c1-6)"
echo "$(uptime)"
