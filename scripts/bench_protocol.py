#!/usr/bin/env python3
"""The article's learning protocol, greybox beside scikit-learn/xgboost, timed back to back on
the same rows and the same folds, and how both scale with the number of rows.

Usage: bench_protocol.py GREYBOX_BIN OUT_DIR [--rows 1000,10000,100000] [--limit-s 120]
                         [--data DATASET.csv] [--jobs 2] [--family all|F,F...]
                         [--demo-tasks protocol,nested] [--rows-tasks one-fit,protocol]
                         [--skip-larger]

1. Protocol (the demo's dataset, or --data): folds from sklearn KFold(5, shuffle,
   random_state=0), given to greybox as a fold column. For each family: grid search over the
   article's grid with those folds (MSE), refit, 1000 bootstrap resamples of the training
   metrics, permutation importance with 30 repeats; then nested CV on top (the same grid search
   inside each outer fold, 5 inner folds). Python runs with n_jobs=--jobs (2 is its fastest
   setting on the 2-core development machine); greybox uses its rayon pool on all cores.
2. Scaling: synthetic rows (μ falling with pressure and speed, 1 % noise) at each --rows size;
   per family one fit of a fixed configuration on each side, and the protocol without nested
   CV. Every timed run is a subprocess with a wall-clock limit (--limit-s); a run that exceeds
   it is reported as "> limit" (and, for greybox, any error message it printed, such as a size
   limit).

One family at a time (`--family`): where the four grids together take too long on either
side, `--family svr` (or a comma list, or `all` for the four) runs each named family's protocol
(and nested CV) as a run of its own: greybox with `fit --families F`, Python with that
family's grid only. `--demo-tasks` / `--rows-tasks` choose what is timed on the demo's dataset
and on the synthetic row counts (an empty value skips that part). `--skip-larger` does not
start a side's run for a family (or the four together) at a row count when the same side
already exceeded --limit-s on the same task at a smaller row count (reported as "skipped").
Where only the Python side exceeded the limit, the ratio is given as a lower bound
(limit / greybox seconds).

Prints a table and writes OUT_DIR/bench-protocol.json. Test-only packages: these never become
runtime dependencies of greybox.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

FEATURES = ["normal_force_N", "sliding_velocity_m_per_min"]
FAMILIES = ["random-forest", "svr", "gradient-boosting", "mlp"]
# one configuration per family for the single-fit scaling runs (greybox flags, sklearn params)
ONE_FIT = {
    "random-forest": (["--rf-n-estimators", "100"], {"n_estimators": 100}),
    "svr": (["--svr-kernel", "rbf", "--svr-c", "10", "--svr-epsilon", "0.01"], {"kernel": "rbf", "C": 10, "epsilon": 0.01}),
    "gradient-boosting": (["--gb-n-estimators", "100", "--gb-max-depth", "5", "--gb-learning-rate", "0.1"],
                          {"n_estimators": 100, "max_depth": 5, "learning_rate": 0.1}),
    "mlp": (["--mlp-hidden", "32x16", "--mlp-activation", "relu", "--mlp-learning-rate", "0.01"],
            {"hidden_layer_sizes": (32, 16), "activation": "relu", "learning_rate_init": 0.01}),
}


# ---------------------------------------------------------------- the Python side (worker)

def sk_family(name, params=None):
    """The scikit-learn/xgboost estimator of a family and the article's grid for it."""
    from sklearn.compose import TransformedTargetRegressor
    from sklearn.ensemble import RandomForestRegressor
    from sklearn.neural_network import MLPRegressor
    from sklearn.pipeline import Pipeline
    from sklearn.preprocessing import StandardScaler
    from sklearn.svm import SVR
    from xgboost import XGBRegressor
    if name == "random-forest":
        return RandomForestRegressor(random_state=0, **(params or {})), {"n_estimators": [10, 50, 100, 200]}
    if name == "svr":
        svr = SVR(**{k: v for k, v in (params or {}).items()})
        return Pipeline([("s", StandardScaler()), ("m", svr)]), {
            "m__C": [0.1, 1, 10, 100], "m__kernel": ["linear", "poly", "rbf", "sigmoid"], "m__epsilon": [0.01, 0.1, 0.2, 0.5]}
    if name == "gradient-boosting":
        return XGBRegressor(tree_method="exact", n_jobs=1, **(params or {})), {
            "n_estimators": [100, 300, 500], "max_depth": [3, 5, 7], "learning_rate": [0.01, 0.05, 0.1]}
    mlp = MLPRegressor(early_stopping=True, max_iter=200, random_state=0, **(params or {}))
    return TransformedTargetRegressor(regressor=Pipeline([("s", StandardScaler()), ("m", mlp)]), transformer=StandardScaler()), {
        "regressor__m__hidden_layer_sizes": [(64, 32), (32, 16)], "regressor__m__activation": ["relu", "tanh"],
        "regressor__m__learning_rate_init": [0.001, 0.01, 0.1]}


def load(path, target):
    import csv
    import numpy as np
    with open(path) as f:
        rows = list(csv.DictReader(f))
    x = np.array([[float(r[c]) for c in FEATURES] for r in rows])
    y = np.array([float(r[target]) for r in rows])
    folds = np.array([int(r["fold"]) for r in rows])
    return x, y, folds


def worker(args):
    """One timed Python task, run in a child process: prints its seconds as JSON."""
    import warnings
    import numpy as np
    from sklearn.inspection import permutation_importance
    from sklearn.model_selection import GridSearchCV, KFold, PredefinedSplit, cross_val_predict
    warnings.filterwarnings("ignore")
    x, y, folds = load(args.data, args.target)
    cv = PredefinedSplit(folds)
    t0 = time.perf_counter()
    for name in args.families.split(","):
        if args.task == "one-fit":
            est, _ = sk_family(name, ONE_FIT[name][1])
            cross_val_predict(est, x, y, cv=PredefinedSplit(folds % 2))  # 2 folds, like greybox --folds 2
            est.fit(x, y)
            continue
        est, grid = sk_family(name)
        best = GridSearchCV(est, grid, cv=cv, scoring="neg_mean_squared_error", n_jobs=args.jobs).fit(x, y).best_estimator_
        pred = best.predict(x)
        rng = np.random.default_rng(42)
        idx = rng.integers(0, len(y), (1000, len(y)))
        for f in (lambda a, b: np.abs(a - b).mean(1), lambda a, b: ((a - b) ** 2).mean(1)):
            np.percentile(f(y[idx], pred[idx]), [2.5, 97.5])
        permutation_importance(best, x, y, n_repeats=30, random_state=42, scoring="r2", n_jobs=args.jobs)
        if args.task == "nested":
            inner = GridSearchCV(est, grid, cv=KFold(5, shuffle=True, random_state=7), scoring="neg_mean_squared_error",
                                 n_jobs=args.jobs)
            cross_val_predict(inner, x, y, cv=cv)
    print(json.dumps({"seconds": time.perf_counter() - t0}))


# ---------------------------------------------------------------- the driver

def with_folds(src, dst, n_rows=None):
    """Copy a dataset CSV with a `fold` column (sklearn KFold(5, shuffle, random_state=0))."""
    import numpy as np
    from sklearn.model_selection import KFold
    lines = Path(src).read_text().splitlines()
    n = len(lines) - 1
    ids = np.zeros(n, dtype=int)
    for k, (_, test) in enumerate(KFold(5, shuffle=True, random_state=0).split(np.arange(n))):
        ids[test] = k
    Path(dst).write_text("\n".join([lines[0] + ",fold"] + [l + f",{ids[i]}" for i, l in enumerate(lines[1:])]) + "\n")


def synthetic(path, n, seed=2026):
    """n rows of μ(F, v): falling with load and speed as the article's data do, 1 % noise."""
    import numpy as np
    rng = np.random.default_rng(seed)
    f = rng.uniform(150, 2000, n)
    v = rng.uniform(20, 250, n)
    mu = 0.2 + 0.45 * (f / 150) ** -0.18 * (v / 20) ** -0.2
    mu *= 1 + 0.01 * rng.standard_normal(n)
    with open(path, "w") as out:
        out.write("normal_force_N,sliding_velocity_m_per_min,cof\n")
        for row in zip(f, v, mu):
            out.write(",".join(repr(float(x)) for x in row) + "\n")


def timed(cmd, limit):
    """(seconds, note) of a subprocess; None seconds past the limit or on failure."""
    t0 = time.perf_counter()
    # Its own process group, so that a run past the limit is ended with everything it started:
    # scikit-learn's n_jobs workers (joblib/loky) outlive a killed parent and would otherwise
    # keep computing beside the next runs.
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=limit)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return None, f"> {limit:g} s"
    finally:
        try:  # workers left behind by a finished run, too
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    wall = time.perf_counter() - t0
    r = subprocess.CompletedProcess(cmd, p.returncode, out, err)
    if r.returncode != 0:
        return None, "error: " + (r.stderr.strip().splitlines() or ["?"])[-1][:160]
    try:
        return json.loads(r.stdout.strip().splitlines()[-1])["seconds"], ""
    except (ValueError, KeyError, IndexError):
        return wall, ""


def greybox_cmd(bin_, data, target, out, flags):
    return [bin_, "fit", "--data", str(data), "--target", target, "--features", ",".join(FEATURES),
            "--out", str(out), "--force", "--json"] + flags


def python_cmd(args, data, target, task, families):
    return [sys.executable, __file__, "--worker", "--task", task, "--data", str(data), "--target", target,
            "--families", families, "--jobs", str(args.jobs)]


def family_runs(args, task):
    """(families, greybox flags) of each run of a task: one run per family for a single fit
    or with --family, otherwise one run of the four families together."""
    if task == "one-fit":
        return [(f, ONE_FIT[f][0]) for f in (args.family or FAMILIES)]
    if args.family:
        return [(f, []) for f in args.family]
    return [(",".join(FAMILIES), [])]


def side_by_side(args, work, data, target, label, tasks, gb_flags=()):
    rows = []
    for task in tasks:
        for fam, fam_flags in family_runs(args, task):
            flags = ["--families", fam, "--fold-column", "fold"] + list(gb_flags) + list(fam_flags)
            if task == "protocol":
                flags += ["--skip-nested"]
            if task == "one-fit":
                flags = ["--families", fam, "--folds", "2", "--skip-nested", "--bootstrap", "1",
                         "--importance-repeats", "1"] + list(fam_flags)
            key = (task, fam)
            if key in args.over_limit.get("greybox", {}):
                g_t, g_note = None, f"skipped (> limit at {args.over_limit['greybox'][key]})"
            else:
                g_t, g_note = timed(greybox_cmd(args.greybox, data, target, work / "gb", flags), args.limit_s)
            if key in args.over_limit.get("python", {}):
                p_t, p_note = None, f"skipped (> limit at {args.over_limit['python'][key]})"
            else:
                p_t, p_note = timed(python_cmd(args, data, target, task, fam), args.limit_s)
            if args.skip_larger:
                for side, t, note in (("greybox", g_t, g_note), ("python", p_t, p_note)):
                    if t is None and note.startswith(">"):
                        args.over_limit.setdefault(side, {})[key] = label
            ratio = p_t / g_t if g_t and p_t else None
            # Python past the limit, greybox within it: the speed-up is at least limit / greybox.
            at_least = args.limit_s / g_t if g_t and p_t is None and p_note.startswith(">") else None
            rows.append({"data": label, "task": task, "families": fam, "greybox_s": g_t, "greybox_note": g_note,
                         "python_s": p_t, "python_note": p_note, "speedup": ratio,
                         "speedup_at_least": at_least, "limit_s": args.limit_s})
            fmt = lambda t, n: f"{t:8.2f} s" if t is not None else f"{n:>10}"
            r = f"{ratio:6.1f}x" if ratio else (f">={at_least:4.1f}x" if at_least else "   -   ")
            print(f"{label:>14}  {task:>8}  {fam:>40}  greybox {fmt(g_t, g_note)}  python {fmt(p_t, p_note)}  {r}",
                  flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("greybox", nargs="?")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--rows", default="1000,10000,100000")
    ap.add_argument("--limit-s", type=float, default=120.0)
    ap.add_argument("--data")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--worker", action="store_true")
    ap.add_argument("--task")
    ap.add_argument("--target", default="cof_apparent")
    ap.add_argument("--families", help="(worker) the families one Python task runs")
    ap.add_argument("--family", help="run one family at a time: all, or a comma list of families")
    ap.add_argument("--demo-tasks", default="protocol,nested",
                    help="tasks on the demo's dataset (protocol, nested; empty: none)")
    ap.add_argument("--rows-tasks", default="one-fit,protocol",
                    help="tasks at each --rows size (one-fit, protocol, nested; empty: none)")
    ap.add_argument("--skip-larger", action="store_true",
                    help="skip a side's run at larger row counts once it exceeded --limit-s")
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    if args.family:
        args.family = FAMILIES if args.family == "all" else args.family.split(",")
        unknown = [f for f in args.family if f not in FAMILIES]
        if unknown:
            ap.error(f"--family: unknown {unknown}; families: {', '.join(FAMILIES)}")
    args.over_limit = {}
    tasks = lambda v: [t for t in v.split(",") if t]
    work = Path(args.out)
    work.mkdir(parents=True, exist_ok=True)
    if args.data is None and tasks(args.demo_tasks):
        subprocess.run([args.greybox, "demo", "--out", str(work / "demo"), "--force"], check=True, capture_output=True)
        args.data = str(work / "demo" / "dataset.csv")
    results = []
    if tasks(args.demo_tasks):
        data = work / "protocol.csv"
        with_folds(args.data, data)
        n_demo = len(Path(data).read_text().splitlines()) - 1
        results += side_by_side(args, work, data, "cof_apparent", f"demo {n_demo} rows", tasks(args.demo_tasks))
    for n in [int(r) for r in args.rows.split(",") if r]:
        path = work / f"rows-{n}.csv"
        synthetic(work / f"raw-{n}.csv", n)
        with_folds(work / f"raw-{n}.csv", path)
        for task in tasks(args.rows_tasks):
            results += side_by_side(args, work, path, "cof", f"{n} rows", [task])
    (work / "bench-protocol.json").write_text(json.dumps(results, indent=2))


if __name__ == "__main__":
    sys.exit(main())
