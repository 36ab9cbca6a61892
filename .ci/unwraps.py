#!/usr/bin/env python3
"""Lists every `unwrap()` / `expect(` in src/ outside test code, and fails unless each
carries a justification: a comment containing `cannot fail` on the same line or on
the comment lines just above it (e.g. `// cannot fail: the list is not empty`).

Skipped: `#[cfg(test)]` items (the brace-matched block after the attribute),
`//` comments (doc comments and doctests included) and string literals, and `.expect(…)?` (a method of our own returning a Result,
not a panic). Variants
such as `unwrap_or`, `unwrap_or_else` and `unwrap_or_default` are not panics and are
not listed.

    python3 .ci/unwraps.py [src]      # exit 1 and a list when one is unjustified
"""
import pathlib
import re
import sys

PANICS = re.compile(r"\.unwrap\(\)|\.expect\(")
# `.expect(…)?`: a method of our own that returns a Result (io/uff's line cursor), not
# Option/Result::expect.
OWN_EXPECT = re.compile(r"\.expect\((?:[^()]|\([^()]*\))*\)\?")
JUSTIFIED = "cannot fail"


def code_only(line):
    """The line without its // comment and string literals (naive but enough here)."""
    out, i, in_str = [], 0, False
    while i < len(line):
        c = line[i]
        if in_str:
            if c == "\\":
                i += 2
                continue
            if c == '"':
                in_str = False
            i += 1
            continue
        if c == '"':
            in_str = True
        elif line.startswith("//", i):
            break
        else:
            out.append(c)
        i += 1
    return "".join(out)


def test_lines(lines):
    """Indices of lines inside `#[cfg(test)]` items."""
    skipped, i = set(), 0
    while i < len(lines):
        if lines[i].strip().startswith("#[cfg(test)]"):
            depth, opened, j = 0, False, i
            while j < len(lines):
                code = code_only(lines[j])
                depth += code.count("{") - code.count("}")
                opened |= "{" in code
                skipped.add(j)
                if opened and depth <= 0 or (not opened and code.rstrip().endswith(";")):
                    break
                j += 1
            i = j + 1
        else:
            i += 1
    return skipped


def justified(lines, k):
    if JUSTIFIED in lines[k]:
        return True
    j = k - 1
    # Up to the line that starts the statement (a method chain spans lines) ...
    while j >= 0 and k - j < 8 and not lines[j].strip().startswith("//"):
        end = code_only(lines[j]).rstrip()
        if not end or end.endswith((";", "{", "}")):
            break
        if JUSTIFIED in lines[j]:
            return True
        j -= 1
    # ... then the comment block just above it.
    while j >= 0 and lines[j].strip().startswith("//"):
        if JUSTIFIED in lines[j]:
            return True
        j -= 1
    return False


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "src")
    found, bad = 0, []
    for path in sorted(root.rglob("*.rs")):
        lines = path.read_text().splitlines()
        skipped = test_lines(lines)
        for k, line in enumerate(lines):
            code = OWN_EXPECT.sub("", code_only(line))
            if k in skipped or not PANICS.search(code):
                continue
            found += 1
            if not justified(lines, k):
                bad.append(f"{path}:{k + 1}: {line.strip()}")
    if bad:
        print(f"{len(bad)} of {found} unwrap()/expect( in {root} without a "
              f"'// {JUSTIFIED}: …' comment on the line or just above:")
        print("\n".join(bad))
        return 1
    print(f"{found} unwrap()/expect( in {root}, each with a '{JUSTIFIED}' comment")
    return 0


if __name__ == "__main__":
    sys.exit(main())
