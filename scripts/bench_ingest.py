#!/usr/bin/env python3
"""Recording ingestion side by side: greybox against pandas (CSV) and npTDMS (TDMS).

Usage: python scripts/bench_ingest.py target/release/greybox [--size-mb 100] [--repeats 5] [--json]

`greybox bench ingest --dir D` writes bench.csv and bench.tdms into D and times greybox's
readers (the CSV one with dialect sniffing switched on, exactly as `identify` uses it); this
script then times, in the same run and on the very same files, pandas.read_csv (C engine;
pyarrow too when installed) and npTDMS (TdmsFile.read plus every channel as a numpy array).
Reported: best and median of R repeats, MB/s, and the speed ratio greybox / peer.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def timed(fn, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("greybox")
    ap.add_argument("--size-mb", type=float, default=100.0)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    import pandas as pd
    from nptdms import TdmsFile

    with tempfile.TemporaryDirectory() as d:
        out = subprocess.run(
            [a.greybox, "bench", "ingest", "--size-mb", str(a.size_mb), "--dir", d,
             "--repeats", str(a.repeats), "--json"],
            check=True, capture_output=True, text=True).stdout
        ours = {r["format"]: r for r in json.loads(out)}
        csv_path = os.path.join(d, "bench.csv")
        tdms_path = os.path.join(d, "bench.tdms")

        def pandas_c():
            df = pd.read_csv(csv_path, engine="c")
            assert len(df) == ours["csv"]["samples"]

        def nptdms():
            f = TdmsFile.read(tdms_path)
            n = [len(ch[:]) for g in f.groups() for ch in g.channels()]
            assert n[0] == ours["tdms"]["samples"]

        rows = []
        peers = [("csv", "pandas read_csv (C engine)", pandas_c), ("tdms", "npTDMS TdmsFile.read", nptdms)]
        try:
            import pyarrow  # noqa: F401

            def pandas_arrow():
                pd.read_csv(csv_path, engine="pyarrow")

            peers.insert(1, ("csv", "pandas read_csv (pyarrow)", pandas_arrow))
        except ImportError:
            pass
        for fmt, name, fn in peers:
            best, med = timed(fn, a.repeats)
            g = ours[fmt]
            rows.append({
                "format": fmt, "file_mb": g["file_mb"], "peer": name,
                "peer_best_s": best, "peer_median_s": med,
                "greybox_best_s": g["best_s"], "greybox_median_s": g["median_s"],
                "speedup": best / g["best_s"],
            })
    if a.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"{'format':6} {'MB':>7} {'peer':30} {'peer best':>10} {'greybox best':>13} {'greybox/peer speed':>19}")
    for r in rows:
        print(f"{r['format']:6} {r['file_mb']:7.1f} {r['peer']:30} {r['peer_best_s']:9.3f}s "
              f"{r['greybox_best_s']:12.3f}s {r['speedup']:18.2f}x")


if __name__ == "__main__":
    sys.exit(main())
