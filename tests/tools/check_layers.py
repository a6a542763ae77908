#!/usr/bin/env python3
"""Checks that svit's source folders include only what their README allows.

usage: check_layers.py [REPO_ROOT]

Each folder of runtime/src and baker/src has a README.md with one line
`May include: a, b, c` (or `May include: nothing`): the other folders its
.cpp and .h files may include. Folder names are unique across both trees
(`scene` is runtime/src/scene, which the baker includes too). A quoted
include must be a public header (`svit/...`), a file of the including
file's own folder (bare name), or `FOLDER/name.h` with FOLDER allowed and
the file there. The allowed lists must form no cycle, so that includes only
point down the layers. Prints one line per problem (file:line: why) and
exits 1 if there is any, else prints the layers bottom first and exits 0.
"""

import os
import re
import sys

ROOTS = ("runtime/src", "baker/src")
ALLOWED = re.compile(r"^May include:\s*(.*?)\s*$", re.M)
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def read_folders(repo):
    """{folder: (path, allowed set)} and the problems met reading them."""
    folders, problems = {}, []
    for root in ROOTS:
        for name in sorted(os.listdir(os.path.join(repo, root))):
            path = os.path.join(root, name)
            if not os.path.isdir(os.path.join(repo, path)):
                problems.append(f"{path}: a file at the top of {root}; every unit lives in a folder")
                continue
            readme = os.path.join(repo, path, "README.md")
            match = ALLOWED.search(open(readme).read()) if os.path.isfile(readme) else None
            if not match:
                problems.append(f"{path}: no README.md with a 'May include:' line")
                continue
            text = match.group(1)
            allowed = set() if text == "nothing" else {a.strip() for a in text.split(",") if a.strip()}
            if name in folders:
                problems.append(f"{path}: folder name also used by {folders[name][0]}")
            folders[name] = (path, allowed)
    for name, (path, allowed) in folders.items():
        for other in sorted(allowed - folders.keys()):
            problems.append(f"{path}/README.md: may include '{other}', which is no folder")
    return folders, problems


def find_cycle(folders):
    """A list of folders that allow each other in a ring, or None."""
    state = {}

    def visit(name, trail):
        state[name] = "open"
        for other in sorted(folders[name][1] & folders.keys()):
            if state.get(other) == "open":
                return trail[trail.index(other):] + [other]
            if other not in state:
                found = visit(other, trail + [other])
                if found:
                    return found
        state[name] = "done"
        return None

    for name in sorted(folders):
        if name not in state:
            found = visit(name, [name])
            if found:
                return found
    return None


def check_include(repo, folders, folder, source, spec):
    """Why the include `spec` in `source` (of `folder`) breaks the layers, or None."""
    if spec.startswith("svit/"):
        return None
    if "/" not in spec:
        if os.path.isfile(os.path.join(repo, os.path.dirname(source), spec)):
            return None
        return f'"{spec}" is not in {folder}/: name its folder ("folder/{spec}")'
    target, _, rest = spec.partition("/")
    if target not in folders:
        return f'"{spec}": {target} is no source folder'
    if target == folder:
        return f'"{spec}": a file of the same folder is included by its bare name'
    if target not in folders[folder][1]:
        return f'"{spec}": {folder} may not include {target} ({folders[folder][0]}/README.md)'
    if not os.path.isfile(os.path.join(repo, folders[target][0], rest)):
        return f'"{spec}": no such file in {folders[target][0]}'
    return None


def layers(folders):
    """Folders bottom first: each after everything it may include."""
    order, placed = [], set()
    while len(order) < len(folders):
        ready = sorted(n for n in folders if n not in placed and folders[n][1] <= placed)
        order += ready
        placed |= set(ready)
    return order


def main():
    repo = sys.argv[1] if len(sys.argv) > 1 else "."
    folders, problems = read_folders(repo)
    cycle = find_cycle(folders)
    if cycle:
        problems.append("the allowed includes form a cycle: " + " -> ".join(cycle))
    for folder, (path, _) in sorted(folders.items()):
        for name in sorted(os.listdir(os.path.join(repo, path))):
            if not name.endswith((".h", ".cpp")):
                continue
            source = os.path.join(path, name)
            for number, line in enumerate(open(os.path.join(repo, source)), 1):
                match = INCLUDE.match(line)
                why = match and check_include(repo, folders, folder, source, match.group(1))
                if why:
                    problems.append(f"{source}:{number}: {why}")
    for problem in problems:
        print(problem)
    if problems:
        return 1
    print("layers, bottom first: " + ", ".join(layers(folders)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
