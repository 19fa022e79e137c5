#!/usr/bin/env python3
"""List functions of the workspace's library and binary sources longer than a limit.

Usage: long_functions.py [LIMIT]   (default 150 lines; test modules are skipped)

A function runs from its `fn` line to the closing brace at the same indentation. Exits 1
when one is longer than LIMIT, so CI keeps long functions from coming back.
"""
import pathlib
import re
import sys

FN = re.compile(r'^(\s*)(pub(\([^)]*\))? )?(const )?(unsafe )?(extern "C" )?fn (\w+)')


def functions(path):
    lines = path.read_text().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("#[cfg(test)]"):
            return  # the test module runs to the end of the file
        m = FN.match(lines[i])
        if m and not lines[i].rstrip().endswith(";"):
            indent = m.group(1)
            j = i + 1
            while j < len(lines) and lines[j].rstrip() != indent + "}":
                j += 1
            yield m.group(7), i + 1, j - i + 1
            i = j
        i += 1


def main():
    limit = int(sys.argv[1]) if len(sys.argv) > 1 else 150
    long = []
    for path in sorted(pathlib.Path("crates").glob("*/src/**/*.rs")):
        for name, line, n in functions(path):
            if n > limit:
                long.append((n, f"{path}:{line}", name))
    for n, where, name in sorted(long, reverse=True):
        print(f"{n:5} lines  {name}  ({where})")
    if long:
        print(f"{len(long)} function(s) longer than {limit} lines: split them along their stages")
        return 1
    print(f"no function longer than {limit} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
