"""Compare two runs of scripts/same_outputs.sh file by file, apart from what no two runs
share: wall times and rates (JSON keys, CSV columns, table cells), provenance files, the
report's build stamps and CalculiX's clock lines. Exit 1 on any other difference."""
import json
import re
import sys
from pathlib import Path

TIMED_KEYS = re.compile(r"^(wall_s|seconds|cut_seconds|.*per_s(_per_core)?|elapsed.*)$")
# The report is drawn from the files compared here, with their timings (fit time per family).
SKIPPED = re.compile(r"(^|/)(provenance\.json|.*\.provenance\.json|report\.html)$")
CLOCK_LINES = re.compile(rb"(Total CalculiX Time|UTIME|UDATE|Time:).*")
DURATIONS = re.compile(rb"\b\d+(\.\d+)? (s|min|ms)\b")


def untimed_json(v):
    if isinstance(v, dict):
        return {k: untimed_json(x) for k, x in v.items() if not TIMED_KEYS.match(k)}
    if isinstance(v, list):
        return [untimed_json(x) for x in v]
    return v


def untimed_csv(data: bytes) -> bytes:
    lines = data.split(b"\n")
    head = lines[0].split(b",")
    keep = [i for i, h in enumerate(head) if not TIMED_KEYS.match(h.decode(errors="replace"))]
    return b"\n".join(b",".join(c for i, c in enumerate(l.split(b",")) if i in keep) for l in lines)


def normalised(path: Path) -> bytes:
    data = path.read_bytes()
    if path.suffix == ".json":
        try:
            return json.dumps(untimed_json(json.loads(data)), sort_keys=True).encode()
        except ValueError:
            return data
    if path.suffix == ".csv":
        return untimed_csv(data)
    return DURATIONS.sub(b"<time>", CLOCK_LINES.sub(b"<clock>", data))


def main(a: Path, b: Path) -> int:
    files_a = sorted(p.relative_to(a).as_posix() for p in a.rglob("*") if p.is_file())
    files_b = sorted(p.relative_to(b).as_posix() for p in b.rglob("*") if p.is_file())
    status = 0
    for f in sorted(set(files_a) ^ set(files_b)):
        print(f"only in one run: {f}")
        status = 1
    for f in sorted(set(files_a) & set(files_b)):
        if SKIPPED.search(f):
            continue
        if normalised(a / f) != normalised(b / f):
            print(f"differs: {f}")
            status = 1
    if status == 0:
        print(f"same outputs: {len(files_a)} files (wall times, provenance and clocks aside)")
    return status


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1]), Path(sys.argv[2])))
