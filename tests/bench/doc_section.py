#!/usr/bin/env python3
"""Puts a bench's table into a document between its markers
`<!-- NAME: begin -->` and `<!-- NAME: end -->` (the table of the last run
replaces the one there). Exits 1, naming the document, where it has no
such markers.

usage: doc_section.py DOC NAME TABLE_FILE
"""
import re
import sys


def put_section(doc, name, table):
    text = open(doc).read()
    begin, end = f"<!-- {name}: begin -->", f"<!-- {name}: end -->"
    if begin not in text or end not in text:
        sys.exit(f"doc_section.py: {doc} has no {name} markers")
    text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: begin + "\n" + table + end,
                  text, flags=re.S)
    open(doc, "w").write(text)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    put_section(sys.argv[1], sys.argv[2], open(sys.argv[3]).read())
