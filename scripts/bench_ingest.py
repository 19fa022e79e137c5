#!/usr/bin/env python3
"""Recording ingestion side by side: greybox against pandas (CSV) and npTDMS (TDMS).

Usage:
    python scripts/bench_ingest.py target/release/greybox [--size-mb 100] [--repeats 5]
                                   [--dir D] [--json]

`greybox bench ingest --dir D --json` writes its benchmark files into D (bench.csv,
bench.tdms, and whatever other dialects it times) and times greybox's readers on them. This
script then times, in the same run and on the very same files:

* CSV: pandas.read_csv with the C engine, and with engine="pyarrow" when pyarrow is
  importable (reported separately);
* TDMS: npTDMS, TdmsFile.read plus every channel's data as a numpy array;
* any other entry greybox reports (CSV dialects: semicolon, decimal comma, tab, preamble...):
  pandas.read_csv with the matching sep / decimal / skiprows, taken from the entry when it
  names them, sniffed from the file otherwise. Entries without a file, or of a kind this
  script does not know, are listed with greybox's numbers alone.

Every reader runs once untimed (which checks that it parses the file and loads lazily
imported modules), then R timed repeats; reported: best and median, MB/s of the best, and
greybox's speed relative to the peer (peer best time / greybox best time: > 1 means greybox is
faster). greybox's TDMS time includes building its recording (waveform time axis included);
npTDMS's does not compute a time axis.

Needs pandas and npTDMS (scripts/requirements-test.txt); pyarrow optional.
"""
import argparse
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

TEXT_SUFFIXES = (".csv", ".txt", ".tsv", ".dat", ".asc")


def timed(fn, repeats):
    """Best and median wall time of `repeats` calls of fn."""
    times = []
    for _ in range(max(1, repeats)):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def find_path(entry, d):
    """The file greybox read for this entry: its `path`, else a guess inside d."""
    p = entry.get("path")
    if isinstance(p, str) and os.path.isfile(p):
        return p
    fmt = str(entry.get("format", ""))
    guesses = {"csv": ["bench.csv"], "tdms": ["bench.tdms"]}.get(fmt, [])
    guesses += [f"bench-{fmt}.*", f"bench_{fmt}.*", f"bench.{fmt}", f"{fmt}.*"]
    for g in guesses:
        hits = sorted(glob.glob(os.path.join(d, g)))
        if hits:
            return hits[0]
    return None


def split_fields(line, sep):
    return re.split(r"\s+", line.strip()) if sep == r"\s+" else line.split(sep)


def is_number(s, decimal):
    s = s.strip().strip('"')
    if decimal == ",":
        s = s.replace(",", ".")
    try:
        float(s)
        return True
    except ValueError:
        return False


def csv_options(path, entry):
    """read_csv options for a delimited text file: from the entry where it names them,
    sniffed from the first 256 KB otherwise."""
    with open(path, "rb") as f:
        head = f.read(256 * 1024)
    text = head.decode("utf-8", errors="replace")
    lines = text.splitlines()
    if len(head) == 256 * 1024 and lines:
        lines = lines[:-1]  # possibly cut
    lines = [ln for ln in lines if ln.strip()]
    tail = lines[-50:]
    sep = entry.get("sep", entry.get("delimiter"))
    if sep is None:
        sep = r"\s+"
        for cand in (";", "\t", "|", ","):
            counts = {ln.count(cand) for ln in tail}
            if len(counts) == 1 and counts != {0}:
                sep = cand
                break
    decimal = entry.get("decimal")
    if decimal is None:
        decimal = "," if sep != "," and re.search(r"\d,\d", "\n".join(tail)) else "."
    opts = {"sep": sep, "decimal": decimal}
    skip = entry.get("skiprows")
    if skip is not None:
        opts["skiprows"] = int(skip)
        return opts
    # header: the first line from which every line has the data rows' number of fields
    n = len(split_fields(tail[-1], sep)) if tail else 0
    first = 0
    for i in range(len(lines) - 1, -1, -1):
        if len(split_fields(lines[i], sep)) != n:
            first = i + 1
            break
    if first < len(lines):
        fields = split_fields(lines[first], sep)
        header_row = not all(is_number(x, decimal) for x in fields if x.strip())
        opts["skiprows"] = first
        if not header_row:
            opts["header"] = None
    # blank lines before the header count for skiprows too
    raw_lines = text.splitlines()
    seen = -1
    for k, ln in enumerate(raw_lines):
        if ln.strip():
            seen += 1
        if seen == opts.get("skiprows", 0):
            opts["skiprows"] = k
            break
    if opts.get("skiprows") == 0:
        del opts["skiprows"]
    return opts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("greybox", help="the greybox binary (e.g. target/release/greybox)")
    ap.add_argument("--size-mb", type=float, default=100.0)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--dir", help="keep the benchmark files here (default: a temporary directory)")
    ap.add_argument("--json", action="store_true", help="print JSON rather than a table")
    a = ap.parse_args()
    import pandas as pd
    from nptdms import TdmsFile

    try:
        import pyarrow  # noqa: F401

        have_arrow = True
    except ImportError:
        have_arrow = False

    tmp = None
    d = a.dir
    if d is None:
        tmp = tempfile.TemporaryDirectory()
        d = tmp.name
    os.makedirs(d, exist_ok=True)
    try:
        cmd = [a.greybox, "bench", "ingest", "--size-mb", str(a.size_mb), "--dir", d,
               "--repeats", str(a.repeats), "--json"]
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            sys.stderr.write(f"{' '.join(cmd)} failed ({run.returncode})\n{run.stderr}")
            return 1
        ours = json.loads(run.stdout)
        if isinstance(ours, dict):  # tolerate a wrapped list
            ours = ours.get("results", [ours])
        results = [compare(e, d, a.repeats, pd, TdmsFile, have_arrow) for e in ours]
    finally:
        if tmp is not None:
            tmp.cleanup()

    if a.json:
        print(json.dumps({
            "size_mb": a.size_mb, "repeats": a.repeats, "pandas": pd.__version__,
            "nptdms": nptdms_version(), "results": results}, indent=2))
        return 0
    print_table(results, a.repeats, pd.__version__)
    return 0


def nptdms_version():
    try:
        from importlib.metadata import version

        return version("nptdms")
    except Exception:  # noqa: BLE001
        return None


def compare(entry, d, repeats, pd, TdmsFile, have_arrow):
    """One greybox entry and its peers' times on the same file."""
    fmt = str(entry.get("format", "?"))
    mb = entry.get("file_mb")
    g_best, g_med = entry.get("best_s"), entry.get("median_s")
    res = {
        "format": fmt,
        "path": None,
        "file_mb": mb,
        "samples": entry.get("samples"),
        "greybox": {"best_s": g_best, "median_s": g_med, "mb_per_s": rate(mb, g_best)},
        "peers": [],
    }
    known = {"format", "path", "file_mb", "samples", "best_s", "median_s", "best_mb_per_s",
             "best_msamples_per_s", "sep", "decimal", "skiprows"}
    extra = {k: v for k, v in entry.items() if k not in known}
    if extra:
        res["greybox_extra"] = extra
    path = find_path(entry, d)
    res["path"] = path
    if path is None:
        return res
    if mb is None:
        res["file_mb"] = mb = os.path.getsize(path) / 1e6
        res["greybox"]["mb_per_s"] = rate(mb, g_best)
    peers = []
    if fmt == "tdms" or path.lower().endswith(".tdms"):
        def nptdms():
            f = TdmsFile.read(path)
            arrays = [ch[:] for g in f.groups() for ch in g.channels()]
            numeric = sum(x.dtype.kind in "biuf" for x in arrays)
            return max((len(x) for x in arrays), default=0), numeric, len(arrays)

        peers.append(("npTDMS TdmsFile.read + numpy", {}, nptdms))
    elif path.lower().endswith(TEXT_SUFFIXES):
        try:
            opts = {} if fmt == "csv" else csv_options(path, entry)
        except Exception as e:  # noqa: BLE001
            res["peers"].append({"reader": "pandas read_csv", "error": f"sniffing: {e}"})
            return res
        engines = [("c", "pandas read_csv (C engine)")]
        if have_arrow and opts.get("sep", ",") != r"\s+":
            engines.append(("pyarrow", "pandas read_csv (pyarrow)"))
        for engine, name in engines:
            def read(engine=engine, opts=opts):
                df = pd.read_csv(path, engine=engine, **opts)
                return len(df), df.select_dtypes("number").shape[1], df.shape[1]

            peers.append((name, opts, read))
    for name, opts, fn in peers:
        row = {"reader": name}
        if opts:
            row["options"] = opts
        try:
            # untimed: checks the parse, loads lazily imported modules
            row["rows"], numeric, columns = fn()
            best, med = timed(fn, repeats)
        except Exception as e:  # noqa: BLE001 (a peer that cannot read a dialect is a result)
            row["error"] = f"{type(e).__name__}: {e}"
            res["peers"].append(row)
            continue
        row.update({"best_s": best, "median_s": med, "mb_per_s": rate(mb, best),
                    "greybox_speedup": best / g_best if g_best else None})
        notes = []
        if res["samples"] is not None and row["rows"] != res["samples"]:
            notes.append(f"read {row['rows']} rows, greybox {res['samples']}")
        if numeric < columns:
            notes.append(f"only {numeric} of {columns} columns read as numbers")
        if notes:
            row["note"] = "; ".join(notes)
        res["peers"].append(row)
    return res


def rate(mb, s):
    return mb / s if mb and s else None


def fmt_s(v):
    return f"{v:9.3f}" if isinstance(v, (int, float)) else f"{'-':>9}"


def print_table(results, repeats, pandas_version):
    print(f"best and median of {repeats} reads; speed-up = peer best / greybox best "
          f"(pandas {pandas_version}, npTDMS {nptdms_version()})")
    w = max([6] + [len(r["format"]) for r in results])
    head = (f"{'format':<{w}} {'MB':>7}  {'reader':<34} {'best s':>9} {'median s':>9} "
            f"{'MB/s':>8} {'greybox speed-up':>17}")
    print(head)
    print("-" * len(head))
    for r in results:
        mb = r["file_mb"]
        mbs = f"{mb:7.1f}" if isinstance(mb, (int, float)) else f"{'-':>7}"
        g = r["greybox"]
        speed = f"{g['mb_per_s']:8.1f}" if g["mb_per_s"] else f"{'-':>8}"
        print(f"{r['format']:<{w}} {mbs}  {'greybox':<34} {fmt_s(g['best_s'])} "
              f"{fmt_s(g['median_s'])} {speed}")
        if r["path"] is None and r["format"] not in ("csv", "tdms"):
            print(f"{'':<{w}} {'':>7}  (no file found for this entry: greybox only)")
        for p in r["peers"]:
            if "error" in p:
                print(f"{'':<{w}} {'':>7}  {p['reader']:<34} failed: {p['error'][:60]}")
                continue
            speed = f"{p['mb_per_s']:8.1f}" if p["mb_per_s"] else f"{'-':>8}"
            up = f"{p['greybox_speedup']:16.2f}x" if p["greybox_speedup"] else ""
            print(f"{'':<{w}} {'':>7}  {p['reader']:<34} {fmt_s(p['best_s'])} "
                  f"{fmt_s(p['median_s'])} {speed} {up}")
            if "options" in p:
                print(f"{'':<{w}} {'':>7}    options: {p['options']}")
            if "note" in p:
                print(f"{'':<{w}} {'':>7}    note: {p['note']}")


if __name__ == "__main__":
    sys.exit(main())
