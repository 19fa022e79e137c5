#!/usr/bin/env python3
"""Run the ```python blocks of a Markdown file in order, in one namespace, inside a fresh
temporary directory (the doc's walkthrough must work as written). The namespace starts
empty: a block may use only what earlier blocks of the page define, as a reader copying them
would. Exit status 1 with the failing block's line on error."""

import os
import sys
import tempfile
import time
import traceback


def blocks(text):
    out, cur, start = [], None, 0
    for i, line in enumerate(text.splitlines(), 1):
        if cur is None and line.strip() == "```python":
            cur, start = [], i + 1
        elif cur is not None and line.strip() == "```":
            out.append((start, "\n".join(cur)))
            cur = None
        elif cur is not None:
            cur.append(line)
    return out


def main():
    doc = os.path.abspath(sys.argv[1])
    namespace = {"__name__": "__doc__"}
    found = blocks(open(doc, encoding="utf-8").read())
    if not found:
        sys.exit(f"{doc}: no python blocks")
    with tempfile.TemporaryDirectory() as d:
        os.chdir(d)
        for line, code in found:
            t = time.perf_counter()
            try:
                exec(compile(code, f"{doc}:{line}", "exec"), namespace)
            except Exception:
                traceback.print_exc()
                sys.exit(f"{doc}: the block at line {line} failed")
            print(f"{os.path.basename(doc)}:{line}: ok ({time.perf_counter() - t:.1f} s)")
    print(f"{doc}: {len(found)} blocks ran")


if __name__ == "__main__":
    main()
