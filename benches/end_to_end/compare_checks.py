"""The steady-state checks of two `dampid identify --json` outputs of the same model,
compared window by window (issue 32: the check's decisions before and after a change):
verdicts, compared periods, kept harmonics, the decisive mismatch's "n sigma" (old over
new), and whether the identified coefficients are the same.

    python3 benches/end_to_end/compare_checks.py OLD.json NEW.json
"""

import json
import statistics
import sys


def main(old_path, new_path):
    old, new = (json.load(open(p)) for p in (old_path, new_path))
    a, b = old["steady_state"]["windows"], new["steady_state"]["windows"]
    if len(a) != len(b):
        sys.exit(f"{len(a)} windows against {len(b)}: not the same model")
    print(f"windows: {len(a)}")
    print(f"steady: {sum(w['steady'] for w in a)} before, {sum(w['steady'] for w in b)} after; "
          f"verdicts that differ: {sum(x['steady'] != y['steady'] for x, y in zip(a, b))}")
    print(f"compared periods that differ: {sum(x['compared'] != y['compared'] for x, y in zip(a, b))}")
    moved = [(x, y) for x, y in zip(a, b) if x["harmonics"] != y["harmonics"]]
    print(f"kept harmonics that differ: {len(moved)}")
    for x, y in moved[:12]:
        gained = sorted(set(y["harmonics"]) - set(x["harmonics"]))
        lost = sorted(set(x["harmonics"]) - set(y["harmonics"]))
        print(f"    window {x['window']} of '{x['record']}': +{gained} -{lost}")
    ratios = sorted(
        x["decisive"]["sigmas"] / y["decisive"]["sigmas"]
        for x, y in zip(a, b)
        if x["decisive"] and y["decisive"] and y["decisive"]["sigmas"] > 0
        and x["decisive"]["measure"] == y["decisive"]["measure"]
    )
    if ratios:
        k = max(len(ratios) // 20, 1) - 1
        print(f"decisive n sigma, old / new, over {len(ratios)} windows: mean {statistics.mean(ratios):.4f}, "
              f"median {statistics.median(ratios):.4f}, 5-95 % {ratios[k]:.3f}-{ratios[-1 - k]:.3f}")
    same = old["report"]["coefficients"] == new["report"]["coefficients"]
    print(f"identified coefficients bit for bit the same: {same}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
