#!/usr/bin/env python3
"""Reads the JSON that checks.js left in chromium's --dump-dom output and fails (exit 1)
on a console error, an element wider than the viewport, SVG text under 12 px as shown, a
plot without a legend, or (with --not-determined) a page that does not say "not
determined". Usage: check.py DOM_FILE NAME [--not-determined]."""
import html
import json
import re
import sys

dom = open(sys.argv[1], encoding="utf-8").read()
name = sys.argv[2]
# The last one: the injected script's own comment names the element too.
found = re.findall(r'<pre id="dampid-check">(\{.*?)</pre>', dom, re.S)
if not found:
    sys.exit(f"{name}: the page did not run its checks (no #dampid-check in the DOM)")
result = json.loads(html.unescape(found[-1]))
failures = []
if result["errors"]:
    failures.append(f"console errors: {result['errors']}")
if result["overflow"] or result["scrollWidth"] > result["viewport"]:
    failures.append(f"wider than the {result['viewport']} px viewport: {result['overflow'][:5]}, scroll width {result['scrollWidth']}")
if result["plots"] == 0:
    failures.append("no plots")
if result["smallText"]:
    failures.append(f"SVG text under 12 px: {result['smallText'][:5]}")
if result["withoutLegend"]:
    failures.append(f"plots without a legend: {result['withoutLegend']}")
if "--not-determined" in sys.argv and not result["notDetermined"]:
    failures.append('no "not determined" on the page')
if failures:
    print(f"{name}: FAIL")
    for f in failures:
        print(f"  {f}")
    sys.exit(1)
print(f"{name}: ok ({result['plots']} plots, smallest SVG text {result['minText']:.1f} px, viewport {result['viewport']} px)")
