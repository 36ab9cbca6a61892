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
# analytic Jacobians, and the same with the exponent's profile interval computed as
# dampid defines it (refits with the exponent fixed, brentq on each end). Like for
# like, in-process on both sides: the library's stages of model_ordinary.toml
# (examples/varpro_residual_speed.rs: the fit without intervals, and identify with
# them), best of REPEAT. Prints the load average beside the times and the ratios.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
repeat=${1:-3}
python=${PYTHON:-/work/venv/bin/python}
dampid="$root/target/release/dampid"
speed="$root/target/release/examples/varpro_residual_speed"
[ -x "$dampid" ] || (cd "$root" && cargo build --release --bin dampid)
[ -x "$speed" ] || (cd "$root" && cargo build --release --example varpro_residual_speed)
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
two_i=$(echo "$json" | "$python" -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["2-point"]["seconds_with_interval"])')
ana_i=$(echo "$json" | "$python" -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["analytic"]["seconds_with_interval"])')
interval=$(echo "$json" | "$python" -c 'import json,sys; print("[%.7f, %.7f]" % tuple(json.load(sys.stdin)["analytic"]["exponent_interval"]))')
stages=$("$speed" "$here/model_ordinary.toml" "$repeat")
fit=$(echo "$stages" | sed -n 's/^fit .*: \([0-9.]*\) s$/\1/p')
all=$(echo "$stages" | sed -n 's/^identify .*: \([0-9.]*\) s$/\1/p')
echo "dampid identify, propagated weighting (model.toml):         $prop s"
echo "dampid identify, ordinary weighting (model_ordinary.toml):  $ord s"
echo "scipy least_squares, jac='2-point':                         $two s"
echo "scipy least_squares, analytic jac:                          $ana s"
echo "scipy with the exponent's profile interval, 2-point:       $two_i s"
echo "scipy with the exponent's profile interval, analytic:      $ana_i s   $interval"
echo "in-process, model_ordinary.toml (examples/varpro_residual_speed.rs):"
echo "$stages" | sed 's/^/    /'
r() { echo "$1 / $2" | bc -l | cut -c1-6; }
echo "ratio dampid identify process (ordinary) / scipy fit, 2-point: $(r "$ord" "$two")"
echo "ratio dampid identify process (ordinary) / scipy fit, analytic: $(r "$ord" "$ana")"
echo "ratio in-process fit, no interval / scipy fit, 2-point: $(r "$fit" "$two")"
echo "ratio in-process fit, no interval / scipy fit, analytic: $(r "$fit" "$ana")"
echo "ratio in-process with interval / scipy with interval, 2-point: $(r "$all" "$two_i")"
echo "ratio in-process with interval / scipy with interval, analytic: $(r "$all" "$ana_i")"
echo "$(uptime)"
