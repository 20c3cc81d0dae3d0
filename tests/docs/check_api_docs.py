#!/usr/bin/env python3
"""Check that the runtime's public headers are documented.

For every header given (runtime/include/usm/*.h):
  - its opening comment says what it offers and states its thread safety
    (a line containing "thread", any case);
  - every function declaration has a comment of its own: a comment ends on
    the line just above the declaration.
Usage: check_api_docs.py HEADER...   exit status 1 with a list of the gaps.
"""
import re
import sys

# A declaration of a function at file scope: "type name(" starting a line.
DECL = re.compile(r"^(?!typedef|#|\s|/|\*|\}|extern \"C\")[A-Za-z_][\w\s\*]*?\b([a-z_][a-z0-9_]*)\s*\(")


def check(path):
    gaps = []
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    end = next((i for i, l in enumerate(lines) if "*/" in l), -1)
    if not lines or not lines[0].startswith("/*") or end < 0:
        gaps.append(f"{path}:1: no opening comment")
    elif not any("thread" in l.lower() for l in lines[: end + 1]):
        gaps.append(f"{path}:1: the opening comment does not state the thread safety")
    for i, line in enumerate(lines):
        m = DECL.match(line)
        if not m:
            continue
        above = lines[i - 1].rstrip() if i > 0 else ""
        if not above.endswith("*/"):
            gaps.append(f"{path}:{i + 1}: {m.group(1)}: no comment above the declaration")
    return gaps


def main():
    gaps = [g for p in sys.argv[1:] for g in check(p)]
    for g in gaps:
        print(g)
    if not sys.argv[1:]:
        print("check_api_docs.py: no headers given")
        return 2
    print(f"{len(sys.argv) - 1} headers, {len(gaps)} gaps")
    return 1 if gaps else 0


if __name__ == "__main__":
    sys.exit(main())
