#!/usr/bin/env python3
"""Checks the relative links of svit's documentation.

usage: check_doc_links.py [REPO_ROOT] [FILE.md ...]

Without files it checks README.md, docs/*.md and, where those folders
exist, docs/bench/*.md and docs/architecture/*.md. Every relative link or
image, [text](path) or ![alt](path), must name an existing file or folder
(relative to the file that links); a #fragment into a Markdown file must
name one of its headings, spelled as GitHub makes heading anchors. Links
with a scheme (https:, mailto:) are not checked. A source file named in
inline code (`bounce_solver.{h,cpp}`, `shaders/index_map*`: names ending in
.h, .cpp, .frag, .vert, .comp, .sh or .py, braces and * allowed) must exist
somewhere in the repository outside build/ and out/, as that path or as the
end of one, so the file tables of docs/architecture.md stay true. Prints one
line per problem (file:line: link: why) and exits 1 if there is any, else 0.
"""

import os
import re
import sys

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
SOURCE_NAME = re.compile(r"^[\w./{},*-]+\.(h|cpp|frag|vert|comp|sh|py)\}?$")
CODE_SPAN = re.compile(r"`([^`]+)`")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def lines_outside_code(text):
    """(line number, line) of the lines outside fenced code blocks."""
    inside = False
    for number, line in enumerate(text.split("\n"), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield number, line


def github_anchor(heading):
    """The anchor GitHub gives a heading: markup and punctuation dropped,
    lower case, spaces as hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links keep their text
    text = text.replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path):
    seen = {}
    anchors = set()
    with open(path, encoding="utf-8") as f:
        for _, line in lines_outside_code(f.read()):
            m = HEADING.match(line)
            if not m:
                continue
            base = github_anchor(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            anchors.add(base if n == 0 else f"{base}-{n}")
    return anchors


def repository_files(root):
    """Every file of the checkout, as paths relative to `root`."""
    files = []
    for directory, subdirs, names in os.walk(root):
        relative = os.path.relpath(directory, root)
        if relative == ".":
            subdirs[:] = [d for d in subdirs if d not in ("build", "out", ".git")]
        files += [os.path.normpath(os.path.join(relative, n)) for n in names]
    return files


def expand(name):
    """`a.{h,cpp}` -> [`a.h`, `a.cpp`]; every brace group, so `{a,b}.{h,cpp}` gives four."""
    m = re.match(r"(.*?)\{([^}]*)\}(.*)", name)
    if not m:
        return [name]
    return [e for part in m.group(2).split(",") for e in expand(m.group(1) + part + m.group(3))]


def source_exists(name, files):
    pattern = re.compile("(^|/)" + re.escape(name).replace(r"\*", "[^/]*") + "$")
    return any(pattern.search(f) for f in files)


def check_file(path, files):
    problems = []
    with open(path, encoding="utf-8") as f:
        text = f.read()
    for number, line in lines_outside_code(text):
        for m in CODE_SPAN.finditer(line):
            name = m.group(1).strip()
            # `a.{h,cpp}` is a source name when its expansions are.
            if SOURCE_NAME.match(name) or all(SOURCE_NAME.match(p) for p in expand(name)):
                problems += [f"{path}:{number}: `{name}`: no such source file in the repository"
                             for part in expand(name) if not source_exists(part, files)][:1]
        line = CODE_SPAN.sub("", line)  # inline code is not a link
        for m in LINK.finditer(line):
            link = m.group(1)
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", link):
                continue
            target, _, fragment = link.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
            if not os.path.exists(resolved):
                problems.append(f"{path}:{number}: {link}: no such file")
                continue
            if fragment and resolved.endswith(".md") and fragment not in anchors_of(resolved):
                problems.append(f"{path}:{number}: {link}: no heading with anchor #{fragment}")
    return problems


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    root = os.path.normpath(root)
    files = argv[2:]
    if not files:
        files = [os.path.join(root, "README.md")]
        for folder in ("docs", os.path.join("docs", "bench"), os.path.join("docs", "architecture")):
            docs = os.path.join(root, folder)
            if os.path.isdir(docs):
                files += sorted(os.path.join(docs, n) for n in os.listdir(docs) if n.endswith(".md"))
    problems = []
    checkout = repository_files(root)
    for path in files:
        problems += check_file(path, checkout)
    for p in problems:
        print(p)
    print(f"check_doc_links: {len(files)} files, {len(problems)} broken links", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
