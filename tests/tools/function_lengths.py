#!/usr/bin/env python3
"""Lists the longest function bodies in C++ sources, for the review check
"no function in baker/ or runtime/ much over 80 lines".

A body is a top-level-or-namespace brace block opened by a line that looks
like a function head (ends with ')' , 'const', 'override' or similar before
'{'). It is a reviewer's tool, not a parser: lambdas count towards the
function that holds them, as a reader sees them.

Usage: function_lengths.py [--limit N] [--top K] DIR...
Exits 1 when any function is longer than --limit lines.
"""
import argparse
import pathlib
import re
import sys

HEAD = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override)?\s*(->\s*[\w:<>]+\s*)?\{\s*$")
NOT_FUNCTION = re.compile(r"^\s*(if|for|while|switch|catch|else|do)\b|\[.*\]\s*\(|=\s*\[|\breturn\b")


def strip(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)
    return line.split("//")[0]


def functions(path):
    lines = path.read_text(errors="replace").splitlines()
    depth, start, name, start_depth = 0, None, None, 0
    in_comment = False
    for number, raw in enumerate(lines, 1):
        line = strip(raw)
        if in_comment:
            if "*/" not in line:
                continue
            line, in_comment = line.split("*/", 1)[1], False
        if "/*" in line and "*/" not in line:
            line, in_comment = line.split("/*", 1)[0], True
        if start is None and HEAD.search(line) and not NOT_FUNCTION.search(line):
            start, name, start_depth = number, raw.strip(), depth
        depth += line.count("{") - line.count("}")
        if start is not None and depth <= start_depth:
            yield number - start + 1, f"{path}:{start}", name
            start = None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--limit", type=int, default=0)
    parser.add_argument("--top", type=int, default=15)
    parser.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    found = []
    for d in args.dirs:
        for path in sorted(pathlib.Path(d).rglob("*")):
            if path.suffix in (".cpp", ".h"):
                found.extend(functions(path))
    found.sort(reverse=True)
    for length, where, name in found[: args.top]:
        print(f"{length:5d}  {where}  {name[:70]}")
    over = [f for f in found if args.limit and f[0] > args.limit]
    if over:
        print(f"{len(over)} functions over {args.limit} lines", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
