#!/usr/bin/env python3
"""Before clang-format: a trailing comment that would push its line past the
column limit moves onto its own line(s) above the code, so clang-format does
not wrap the code around it. `x = 1;  ///< why` becomes `/// why` then
`x = 1;`; `x = 1;  // why` becomes `// why` then `x = 1;`. Lines inside
block comments, preprocessor lines and string-bearing lines are left alone.

Usage: lift_long_comments.py [--limit N] FILE...
"""
import argparse
import re
import textwrap

TRAILING = re.compile(r"^(?P<indent>\s*)(?P<code>\S.*?)\s+(?P<mark>///<|//)\s?(?P<text>.*)$")


def lift(lines, limit):
    out = []
    for line in lines:
        m = TRAILING.match(line)
        if len(line) <= limit or not m or line.lstrip().startswith(("//", "#", "*", "/*")):
            out.append(line)
            continue
        code = m.group("code")
        if '"' in code or "'" in code or code.endswith("\\"):
            out.append(line)
            continue
        indent = m.group("indent")
        mark = "///" if m.group("mark") == "///<" else "//"
        width = max(30, limit - len(indent) - len(mark) - 1)
        for piece in textwrap.wrap(m.group("text"), width) or [""]:
            out.append(f"{indent}{mark} {piece}".rstrip())
        out.append(f"{indent}{code}")
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--limit", type=int, default=100)
    parser.add_argument("files", nargs="+")
    args = parser.parse_args()
    for path in args.files:
        with open(path) as f:
            text = f.read()
        lines = text.split("\n")
        lifted = lift(lines, args.limit)
        if lifted != lines:
            with open(path, "w") as f:
                f.write("\n".join(lifted))


if __name__ == "__main__":
    main()
