#!/usr/bin/env python3
"""Lines of code of the workspace's library and binary sources, tests left out.

Usage: code_size.py [--max-file N] [--max-crate-share PERCENT] [--max-share CRATE=PERCENT ...]

A line of code is a line that is neither blank nor only a comment (`//`, `///`, `//!`), in
`crates/*/src/**/*.rs`, before the file's `#[cfg(test)]` module (test modules run to the end of
their file here) and outside `src/**/tests/` folders. Prints each crate's share of the whole and
the largest files. Exits 1 when a file has more than `--max-file` lines of code or a crate's
share is above `--max-crate-share` (every crate) or its own `--max-share`, so CI keeps rooms
from growing back.
"""
import argparse
import collections
import pathlib
import sys


def lines_of_code(path):
    n = 0
    for line in path.read_text().split("\n"):
        if line.startswith("#[cfg(test)]"):
            break
        s = line.strip()
        if s and not s.startswith("//"):
            n += 1
    return n


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--max-file", type=int)
    ap.add_argument("--max-crate-share", type=float)
    ap.add_argument("--max-share", action="append", default=[])
    ap.add_argument("--top", type=int, default=12)
    args = ap.parse_args()
    files = {}
    for path in sorted(pathlib.Path("crates").glob("*/src/**/*.rs")):
        if "tests" in path.relative_to(path.parts[0], path.parts[1], "src").parts[:-1]:
            continue
        files[path] = lines_of_code(path)
    crates = collections.Counter()
    for path, n in files.items():
        crates[path.parts[1]] += n
    total = sum(crates.values())
    print(f"{total} lines of code in {len(files)} files")
    for crate, n in crates.most_common():
        print(f"{n:7} {100 * n / total:5.1f} %  {crate}")
    print("largest files:")
    for path, n in sorted(files.items(), key=lambda kv: -kv[1])[: args.top]:
        print(f"{n:7}  {path}")
    failed = False
    if args.max_file is not None:
        for path, n in files.items():
            if n > args.max_file:
                print(f"{path}: {n} lines of code, more than {args.max_file}: split it along its seams")
                failed = True
    if args.max_crate_share is not None:
        for crate, n in crates.items():
            share = 100 * n / total
            if share > args.max_crate_share:
                print(f"{crate}: {share:.1f} % of the code, more than {args.max_crate_share:g} %: "
                      "split it along its purposes")
                failed = True
    for rule in args.max_share:
        crate, percent = rule.split("=")
        share = 100 * crates[crate] / total
        if share > float(percent):
            print(f"{crate}: {share:.1f} % of the code, more than {percent} %")
            failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
