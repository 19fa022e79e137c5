#!/usr/bin/env python3
"""Compare two `greybox demo` output directories file by file.

Usage: compare_demo.py OLD_DIR NEW_DIR

Files are compared byte for byte. JSON files that differ are compared again with the fields
that legitimately differ between two runs masked: the recorded command line (binary path,
output directory), wall-clock times, and the content hashes that cover them; other files
that differ are compared again without the wall-clock lines CalculiX writes into its logs
and result files. Exits 1 when a
file is missing on one side or differs beyond those fields.
"""
import hashlib
import json
import pathlib
import sys

# Lines with the wall clock that CalculiX writes into its own logs and result files.
CLOCK_LINES = (b"Total CalculiX Time", b"1UTIME", b"1UDATE")
MASKED = {"command", "command_line", "seconds", "wall_s", "particle_steps_per_s",
          "particle_steps_per_s_per_core", "content_hash"}


def without_clock(data):
    return b"\n".join(l for l in data.split(b"\n") if not any(c in l for c in CLOCK_LINES))


def files(root):
    return {p.relative_to(root).as_posix(): p for p in root.rglob("*") if p.is_file()}


def masked(value):
    if isinstance(value, dict):
        return {k: masked(v) for k, v in value.items() if k not in MASKED}
    if isinstance(value, list):
        return [masked(v) for v in value]
    return value


def main():
    old, new = (pathlib.Path(a) for a in sys.argv[1:3])
    a, b = files(old), files(new)
    bad = 0
    for name in sorted(set(a) - set(b)):
        print(f"only in {old}: {name}")
        bad += 1
    for name in sorted(set(b) - set(a)):
        print(f"only in {new}: {name}")
        bad += 1
    same = masked_same = clock_same = 0
    for name in sorted(set(a) & set(b)):
        x, y = a[name].read_bytes(), b[name].read_bytes()
        if x == y:
            same += 1
        elif name.endswith(".json") and masked(json.loads(x)) == masked(json.loads(y)):
            masked_same += 1
        elif without_clock(x) == without_clock(y):
            clock_same += 1
        else:
            print(f"differs: {name} ({hashlib.sha256(x).hexdigest()[:12]} vs {hashlib.sha256(y).hexdigest()[:12]})")
            bad += 1
    print(f"{same} files byte-identical, {masked_same} equal apart from command line, times and hashes, "
          f"{clock_same} equal apart from CalculiX's clock lines, {bad} differences")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
