#!/usr/bin/env bash
# Campaign benchmarks (issue 32), one sitting, with examples/python/campaign_dask.py:
#
#   1. small records (4 DOFs, 1,000 samples): records per second per core through the
#      map (`regressor_rows`, one process) and through single-process `identify` on a
#      list, default and measured pipelines (printed by the example's check);
#   2. scaling: 400 records of 10^5 samples (windows of 10 periods), the map, stack and
#      fit on a LocalCluster of 1 and of 2 worker processes (best of REPEATS each);
#   3. memory: 10^4 records generated on two `dask worker` processes of a `dask
#      scheduler` on localhost (not a LocalCluster), the client's peak RSS.
#
#   source /path/to/venv/bin/activate      # dampid (pip install ./python), numpy, dask[distributed]
#   bash benches/campaign/run.sh [REPEATS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
example=$root/examples/python/campaign_dask.py
repeats=${1:-3}
export PYTHONPATH=$root/examples/python${PYTHONPATH:+:$PYTHONPATH}

echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "dampid: $(git -C "$root" rev-parse --short HEAD); $(python -c 'import dask, numpy; print("dask", dask.__version__, "numpy", numpy.__version__)')"

echo "== 1. small records: 4 DOFs x 1,000 samples, 2,000 records"
for pipeline in default measured; do
    python "$example" --records 2000 --samples 1000 --per-task 250 --workers 2 --pipeline "$pipeline" 2>/dev/null \
        | grep -E 'records \(|one core|single-process|bit for bit'
done

echo "== 2. scaling: 400 records x 10^5 samples, windows of 10 periods (best of $repeats)"
for workers in 1 2; do
    best=
    for _ in $(seq "$repeats"); do
        line=$(python "$example" --records 400 --samples 100000 --cycles 10 --per-task 10 \
            --workers "$workers" --no-check 2>/dev/null | grep 'Dask map')
        seconds=$(echo "$line" | sed -E 's/.*: ([0-9.]+) s on.*/\1/')
        echo "   $workers worker(s): $line"
        if [ -z "$best" ] || awk "BEGIN {exit !($seconds < $best)}"; then best=$seconds; fi
    done
    echo "   best with $workers worker(s): $best s"
    eval "best_$workers=$best"
done
awk "BEGIN {printf \"   speed-up, 2 workers against 1: %.2fx\n\", $best_1 / $best_2}"

echo "== 3. memory: 10^4 records on a dask scheduler and two dask worker processes"
port=$(python -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
scratch=$(mktemp -d)
dask scheduler --host 127.0.0.1 --port "$port" --no-dashboard >"$scratch/scheduler.log" 2>&1 &
pids=$!
for w in 1 2; do
    RAYON_NUM_THREADS=1 dask worker "tcp://127.0.0.1:$port" --nthreads 1 --no-dashboard --local-directory "$scratch" >"$scratch/worker$w.log" 2>&1 &
    pids="$pids $!"
done
trap 'kill $pids 2>/dev/null || true; rm -rf "$scratch"' EXIT
python "$example" --records 10000 --per-task 250 --scheduler "tcp://127.0.0.1:$port" --wait-workers 2 --no-check 2>/dev/null \
    | grep -E 'records \(|Dask map'
