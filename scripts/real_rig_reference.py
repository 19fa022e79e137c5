#!/usr/bin/env python3
"""Independent reference friction coefficients for the real tribometer exports.

Reads every ``[[file]]`` of ``tests/data/real-rigs/manifest.toml`` with pandas
(the raw files themselves are kept outside the project, in ``../shared/data/real-rigs``
beside the checkout, or the directory given as the second argument),
using only the explicit settings written there (delimiter, decimal mark,
encoding, line terminator, header line, footer lines, block layout), and writes
``tests/data/real-rigs/reference.csv`` with the columns

    path,step,normal_force_N,mu_reference,mu_std,rule,notes

This script is deliberately independent of greybox: it uses Python 3
(tomllib), numpy and pandas only, and never imports or calls greybox code.

Steady-state rules
------------------
Sliding samples: rows whose speed column is > 0 when the file has a speed
column; otherwise every row.  Time is the manifest's time column (seconds).

* continuous (one load and speed in the file): the window is the final 50 %
  of the sliding time (ASTM G99 practice: steady state after run-in).
  ``mu_reference`` is the mean of |F_t| / |F_n| over the window when the file
  has a friction-force column and a normal force (column, or a constant load
  stated outside the table, ``normal_force_value_N``); otherwise the mean of
  the rig's COF column.  ``mu_std`` is the standard deviation of the same
  per-sample ratio over the window.  ``notes`` also gives the least-squares
  linear drift slope of the ratio over the window (per second) and, where both
  forces and a COF column exist, ``mu_forces`` and ``mu_cof`` separately.
* stepped (several loads/speeds in one file): the same rule applied to each
  step separately, the window being the last 50 % of that step's time; step
  numbers are the file's own step numbers.
* reciprocating: per cycle, only the middle 50 % of each stroke (by stroke
  position) is used, mu = |F_t| / |F_n| there, the stroke direction being
  the sign of the position increment; the reference is the mean over the
  strokes of the final 50 % of cycles, also reported per direction.  (No kept
  file is reciprocating at present: the reciprocating exports found were
  unlicensed, see NOT-KEPT.md; the rule is implemented for when one is added.)

Normal force is reported in newtons: the mean |F_n| over the window, converted
from the manifest's ``force_unit`` (N, or g / kgf with g = 9.80665 m/s^2).

Usage:  python3 scripts/real_rig_reference.py [repo_root]
"""

from __future__ import annotations

import io
import sys
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

G0 = 9.80665


def force_scale(unit: str) -> float:
    u = unit.strip().split()[0].lower() if unit.strip() else "n"
    return {"n": 1.0, "mn": 1e-3, "kn": 1e3, "g": G0 * 1e-3, "kgf": G0, "kg": G0}[u]


def clean_columns(df: pd.DataFrame) -> pd.DataFrame:
    df.columns = [str(c).strip() for c in df.columns]
    return df


def to_num(s: pd.Series, decimal: str) -> pd.Series:
    """Numeric conversion of a column that pandas may have left as text."""
    if s.dtype.kind in "if":
        return s.astype(float)
    t = s.astype(str).str.strip()
    if decimal == ",":
        t = t.str.replace(".", "", regex=False).str.replace(",", ".", regex=False)
    return pd.to_numeric(t, errors="coerce")


def read_table(path: Path, spec: dict) -> pd.DataFrame:
    kw = dict(
        sep=spec["delimiter"],
        decimal=spec["decimal"],
        encoding=spec["encoding"],
        skiprows=spec.get("skiprows", 0),
        engine="python",
        index_col=False,  # rows may carry more trailing separators than the header (.dwf ';;')
    )
    if spec.get("skipfooter"):
        kw["skipfooter"] = spec["skipfooter"]
    term = spec.get("lineterminator")
    if term:
        # the python engine does not take lineterminator; translate bare CR explicitly
        text = path.read_bytes().decode(spec["encoding"]).replace("\r", "\n")
        df = pd.read_csv(io.StringIO(text), **{k: v for k, v in kw.items() if k != "encoding"})
    else:
        df = pd.read_csv(path, **kw)
    df = clean_columns(df)
    return df.loc[:, [c for c in df.columns if c and not c.startswith("Unnamed")]]


def read_pcs_steps(path: Path, spec: dict) -> list[tuple[int, pd.DataFrame]]:
    """PCS Multitracker layout: 'Step N started ...' preamble, then a header
    line starting with 'Step Time (s)', data rows, a blank line.  MAPPER steps
    have no table and are skipped."""
    lines = path.read_bytes().decode(spec["encoding"]).splitlines()
    out, step, i = [], None, 0
    while i < len(lines):
        ln = lines[i]
        if ln.startswith("Step ") and " started at " in ln:
            step = int(ln.split()[1])
        if ln.startswith(spec["time_column"] + spec["delimiter"]):
            j = i + 1
            while j < len(lines) and lines[j].strip():
                j += 1
            block = "\n".join(lines[i:j])
            df = pd.read_csv(io.StringIO(block), sep=spec["delimiter"], decimal=spec["decimal"])
            df = clean_columns(df)
            out.append((step, df))
            i = j
        i += 1
    return out


def window_stats(df: pd.DataFrame, spec: dict, last_fraction: float = 0.5) -> dict:
    dec = spec["decimal"]
    t = to_num(df[spec["time_column"]], dec).to_numpy()
    keep = np.isfinite(t)
    if spec.get("speed_column"):
        v = to_num(df[spec["speed_column"]], dec).to_numpy()
        keep &= np.isfinite(v) & (np.abs(v) > 0)
    scale = force_scale(spec.get("force_unit", "N"))
    ff = to_num(df[spec["friction_force_column"]], dec).to_numpy() if spec.get("friction_force_column") else None
    if spec.get("normal_force_column"):
        fn = to_num(df[spec["normal_force_column"]], dec).to_numpy()
        fn_src = spec["normal_force_column"]
    elif "normal_force_value_N" in spec:
        fn = np.full(len(df), spec["normal_force_value_N"] / scale)
        fn_src = "constant %g N from file name" % spec["normal_force_value_N"]
    else:
        fn, fn_src = None, ""
    cof = to_num(df[spec["cof_column"]], dec).to_numpy() if spec.get("cof_column") else None

    t, idx = t[keep], np.flatnonzero(keep)
    t0, t1 = t.min(), t.max()
    w = idx[t >= t0 + (1.0 - last_fraction) * (t1 - t0)]
    tw = to_num(df[spec["time_column"]], dec).to_numpy()[w]

    res = {"n": len(w), "t_from": float(tw.min()), "t_to": float(tw.max())}
    if ff is not None and fn is not None:
        r = np.abs(ff[w]) / np.abs(fn[w])
        r = r[np.isfinite(r)]
        res["mu_forces"] = float(np.mean(r))
        res["series"] = ("forces", r, tw[: len(r)])
    if cof is not None:
        c = cof[w][np.isfinite(cof[w])]
        res["mu_cof"] = float(np.mean(c))
        if "series" not in res:
            res["series"] = ("cof", c, tw[: len(c)])
    if fn is not None:
        res["normal_force_N"] = float(np.nanmean(np.abs(fn[w]))) * scale
    res["fn_src"] = fn_src
    kind, r, tr = res.pop("series")
    res["mu_reference"] = float(np.mean(r))
    res["mu_std"] = float(np.std(r, ddof=1)) if len(r) > 1 else 0.0
    res["drift_per_s"] = float(np.polyfit(tr, r, 1)[0]) if len(r) > 2 else float("nan")
    res["basis"] = kind
    return res


def reciprocating_stats(df: pd.DataFrame, spec: dict) -> dict:
    """Middle 50 % of each stroke; strokes of the final 50 % of cycles."""
    dec = spec["decimal"]
    x = to_num(df[spec["position_column"]], dec).to_numpy()
    ff = to_num(df[spec["friction_force_column"]], dec).to_numpy()
    fn = to_num(df[spec["normal_force_column"]], dec).to_numpy()
    d = np.sign(np.diff(x, prepend=x[0]))
    d[d == 0] = np.nan
    d = pd.Series(d).ffill().bfill().to_numpy()
    stroke_id = np.cumsum(np.r_[0, d[1:] != d[:-1]])
    rows = []
    for s in np.unique(stroke_id):
        m = stroke_id == s
        xs = x[m]
        lo, hi = np.min(xs), np.max(xs)
        if hi <= lo:
            continue
        mid = m & (x >= lo + 0.25 * (hi - lo)) & (x <= hi - 0.25 * (hi - lo))
        mu = np.abs(ff[mid]) / np.abs(fn[mid])
        rows.append((s, d[m][0], float(np.nanmean(mu)), float(np.nanmean(np.abs(fn[mid])))))
    st = pd.DataFrame(rows, columns=["stroke", "dir", "mu", "fn"])
    late = st[st["stroke"] >= st["stroke"].max() / 2.0]
    scale = force_scale(spec.get("force_unit", "N"))
    return {
        "mu_reference": float(late["mu"].mean()),
        "mu_std": float(late["mu"].std(ddof=1)),
        "mu_fwd": float(late.loc[late["dir"] > 0, "mu"].mean()),
        "mu_bwd": float(late.loc[late["dir"] < 0, "mu"].mean()),
        "normal_force_N": float(late["fn"].mean()) * scale,
        "n": len(late),
    }


def fmt(x: float) -> str:
    return "" if x is None or not np.isfinite(x) else "%.6g" % x


def main(root: Path, corpus: Path) -> int:
    base = root / "tests/data/real-rigs"
    manifest = tomllib.loads((base / "manifest.toml").read_text(encoding="utf-8"))
    out = []
    for spec in manifest["file"]:
        path = corpus / spec["path"]
        mode = spec["mode"]
        if mode == "reciprocating":
            r = reciprocating_stats(read_table(path, spec), spec)
            out.append(dict(path=spec["path"], step=0, normal_force_N=fmt(r["normal_force_N"]),
                            mu_reference=fmt(r["mu_reference"]), mu_std=fmt(r["mu_std"]),
                            rule="reciprocating: mid-50% of each stroke, strokes of final 50% of cycles",
                            notes="mu_fwd=%s; mu_bwd=%s; strokes=%d" % (fmt(r["mu_fwd"]), fmt(r["mu_bwd"]), r["n"])))
            continue
        if spec.get("blocks") == "pcs-step":
            parts = read_pcs_steps(path, spec)
        else:
            parts = [(0, read_table(path, spec))]
        for step, df in parts:
            r = window_stats(df, spec)
            notes = ["basis=%s" % r["basis"]]
            if "mu_forces" in r:
                notes.append("mu_forces=%s" % fmt(r["mu_forces"]))
            if "mu_cof" in r:
                notes.append("mu_cof=%s" % fmt(r["mu_cof"]))
            notes.append("drift=%s /s" % fmt(r["drift_per_s"]))
            notes.append("window t=%s..%s s, n=%d" % (fmt(r["t_from"]), fmt(r["t_to"]), r["n"]))
            if r["fn_src"]:
                notes.append("Fn: %s" % r["fn_src"])
            rule = ("continuous: final 50% of sliding time" if mode == "continuous"
                    else "stepped: last 50% of each step")
            out.append(dict(path=spec["path"], step=step if mode == "stepped" else 0,
                            normal_force_N=fmt(r.get("normal_force_N", float("nan"))),
                            mu_reference=fmt(r["mu_reference"]), mu_std=fmt(r["mu_std"]),
                            rule=rule, notes="; ".join(notes)))
    pd.DataFrame(out).to_csv(base / "reference.csv", index=False, lineterminator="\n")
    print((base / "reference.csv").read_text())
    return 0


if __name__ == "__main__":
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1]
    corpus = Path(sys.argv[2]) if len(sys.argv) > 2 else root.parent / "shared" / "data" / "real-rigs"
    sys.exit(main(root, corpus))
