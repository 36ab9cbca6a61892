#!/usr/bin/env python3
"""Compares two snapshot folders written by snapshot.sh, file by file.

For each file: 'identical' (same bytes), or for JSON the count of numbers that differ
and the largest relative difference (|a - b| / max(|a|, |b|)), or for text the number of
differing lines and the largest relative difference of the numbers on them. Exit code 1
when any file differs beyond --tolerance (default 0: bit for bit), or is missing.

usage: compare.py BEFORE AFTER [--tolerance 1e-12]
"""
import json, os, re, sys

NUM = re.compile(r'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?')


def rel(a, b):
    if a == b:
        return 0.0
    scale = max(abs(a), abs(b))
    return abs(a - b) / scale if scale > 0 else abs(a - b)


def walk(a, b, path, diffs):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                diffs.append((f'{path}.{k}', 'missing on one side'))
            else:
                walk(a[k], b[k], f'{path}.{k}', diffs)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            diffs.append((path, f'length {len(a)} vs {len(b)}'))
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f'{path}[{i}]', diffs)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if a != b:
            diffs.append((path, rel(float(a), float(b))))
    elif a != b:
        diffs.append((path, f'{a!r} vs {b!r}'[:160]))


def text_diffs(a, b):
    la, lb = a.splitlines(), b.splitlines()
    diffs = []
    if len(la) != len(lb):
        diffs.append(('lines', f'{len(la)} vs {len(lb)}'))
    for i, (x, y) in enumerate(zip(la, lb)):
        if x == y:
            continue
        na, nb = NUM.findall(x), NUM.findall(y)
        if len(na) == len(nb) and NUM.sub('#', x) == NUM.sub('#', y):
            worst = max(rel(float(p), float(q)) for p, q in zip(na, nb))
            diffs.append((f'line {i + 1}', worst))
        else:
            diffs.append((f'line {i + 1}', f'{x!r} vs {y!r}'[:200]))
    return diffs


def files(root):
    out = set()
    for d, _, fs in os.walk(root):
        for f in fs:
            out.add(os.path.relpath(os.path.join(d, f), root))
    return out


def main():
    args = sys.argv[1:]
    tol = 0.0
    if '--tolerance' in args:
        i = args.index('--tolerance')
        tol = float(args[i + 1])
        del args[i:i + 2]
    before, after = args
    fa, fb = files(before), files(after)
    bad = 0
    same = 0
    for name in sorted(fa | fb):
        if name not in fa or name not in fb:
            print(f'MISSING  {name} (only in {"before" if name in fa else "after"})')
            bad += 1
            continue
        # The output folder's own path appears in messages ("wrote DIR/report.html").
        a = open(os.path.join(before, name), 'rb').read().replace(before.rstrip('/').encode(), b'OUT')
        b = open(os.path.join(after, name), 'rb').read().replace(after.rstrip('/').encode(), b'OUT')
        if a == b:
            same += 1
            continue
        ta, tb = a.decode('utf-8', 'replace'), b.decode('utf-8', 'replace')
        try:
            diffs = []
            walk(json.loads(ta), json.loads(tb), '', diffs)
        except ValueError:
            diffs = text_diffs(ta, tb)
        numeric = [d for _, d in diffs if isinstance(d, float)]
        other = [(p, d) for p, d in diffs if not isinstance(d, float)]
        worst = max(numeric, default=0.0)
        within = not other and worst <= tol
        if not within:
            bad += 1
        tag = 'within' if within else 'DIFFERS'
        print(f'{tag:8} {name}: {len(numeric)} numbers differ (largest relative {worst:.2e}), '
              f'{len(other)} other differences')
        for p, d in other[:5]:
            print(f'           {p}: {d}')
    print(f'{same} identical, {bad} differ beyond {tol:g}, of {len(fa | fb)}')
    sys.exit(1 if bad else 0)


main()
