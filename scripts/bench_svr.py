#!/usr/bin/env python3
"""One SVR fit (rbf, C 10, ε 0.01: bench_protocol's ONE_FIT), greybox beside scikit-learn, on
bench_protocol's synthetic μ(F, v) rows at each size: the "one fit" of bench_protocol.py for
the SVR alone (2-fold CV plus the final fit, start-up and CSV read included).

Usage: bench_svr.py GREYBOX_BIN OUT_DIR [ROWS=1000,10000,100000] [LIMIT_S=120] [--no-peer]
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_protocol as bp  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("greybox")
    ap.add_argument("out")
    ap.add_argument("rows", nargs="?", default="1000,10000,100000")
    ap.add_argument("limit_s", nargs="?", type=float, default=120.0)
    ap.add_argument("--no-peer", action="store_true")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    args = argparse.Namespace(greybox=a.greybox, limit_s=a.limit_s, jobs=2, family=["svr"], over_limit={},
                              skip_larger=False)
    for n in [int(r) for r in a.rows.split(",") if r]:
        path = out / f"rows-{n}.csv"
        if not path.exists():
            bp.synthetic(out / f"raw-{n}.csv", n)
            bp.with_folds(out / f"raw-{n}.csv", path)
        if a.no_peer:
            flags = ["--families", "svr", "--folds", "2", "--skip-nested", "--bootstrap", "1",
                     "--importance-repeats", "1"] + bp.ONE_FIT["svr"][0]
            t, note = bp.timed(bp.greybox_cmd(a.greybox, path, "cof", out / "gb", flags), a.limit_s)
            print(f"{n:>8} rows  greybox {t if t is not None else note}", flush=True)
        else:
            bp.side_by_side(args, out, path, "cof", f"{n} rows", ["one-fit"])


if __name__ == "__main__":
    sys.exit(main())
