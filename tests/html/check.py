#!/usr/bin/env python3
"""Reads the JSON that checks.js left in chromium's --dump-dom output and fails (exit 1)
on a console error, an element wider than the viewport, SVG text under 12 px as shown, a
plot without a legend, or (with --not-determined) a page that does not say "not
determined"; with --max-height PX a page taller than PX as laid out, with --expect TEXT
a page (its DOM) without TEXT, with --absent TEXT one with it, with --expect-plot TEXT
no plot (SVG) holding TEXT (each repeatable).
Usage: check.py DOM_FILE NAME [--not-determined] [--max-height PX] [--expect TEXT]...
[--absent TEXT]... [--expect-plot TEXT]..."""
import argparse
import html
import json
import re
import sys

parser = argparse.ArgumentParser()
parser.add_argument("dom")
parser.add_argument("name")
parser.add_argument("--not-determined", action="store_true")
parser.add_argument("--max-height", type=float)
parser.add_argument("--expect", action="append", default=[])
parser.add_argument("--absent", action="append", default=[])
parser.add_argument("--expect-plot", action="append", default=[])
args = parser.parse_args()
dom = open(args.dom, encoding="utf-8").read()
name = args.name
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
if args.not_determined and not result["notDetermined"]:
    failures.append('no "not determined" on the page')
if args.max_height is not None and result["height"] > args.max_height:
    failures.append(f"{result['height']} px tall at {result['viewport']} px wide, more than {args.max_height:.0f}")
# The page as written: the DOM before the injected results.
page = html.unescape(dom[: dom.rfind('<pre id="dampid-check">')])
for text in args.expect:
    if text not in page:
        failures.append(f"no {text!r} on the page")
for text in args.absent:
    if text in page:
        failures.append(f"{text!r} on the page")
plots = re.findall(r"<svg.*?</svg>", page, re.S)
for text in args.expect_plot:
    if not any(text in svg for svg in plots):
        failures.append(f"no plot with {text!r}")
if failures:
    print(f"{name}: FAIL")
    for f in failures:
        print(f"  {f}")
    sys.exit(1)
print(f"{name}: ok ({result['plots']} plots, smallest SVG text {result['minText']:.1f} px, viewport {result['viewport']} px, {result['height']} px tall)")
