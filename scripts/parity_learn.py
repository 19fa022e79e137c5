#!/usr/bin/env python3
"""Parity of greybox's four model families with scikit-learn (RF, SVR, MLP) and xgboost
(boosted trees): held-out R² with the same hyperparameters and the same folds.

Usage: parity_learn.py GREYBOX_BIN OUT_DIR [--quick] [--markdown docs/parity-learn.md]

Two datasets: the example dataset (`greybox demo`: normal force and sliding velocity → COF on
the article's 10 × 21 grid) and a second one generated here with different structure
(three scattered features incl. temperature, a sine term, heavier noise). Folds: sklearn
KFold(5, shuffle, random_state=0), passed to greybox as a fold column. Stochastic families
(RF, MLP) are averaged over ten seeds on both sides (MLP training with early stopping on
~20 validation rows is strongly seed-dependent; the seed spread is reported). Pass: |ΔR²| ≤ 0.01.
Test-only: these packages are never runtime dependencies of greybox.
"""
import argparse
import warnings
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from sklearn.compose import TransformedTargetRegressor
from sklearn.ensemble import RandomForestRegressor
from sklearn.metrics import r2_score
from sklearn.model_selection import KFold
from sklearn.neural_network import MLPRegressor
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVR
from xgboost import XGBRegressor

TOL = 0.01
SEEDS = list(range(10))


def second_dataset(path: Path) -> None:
    rng = np.random.default_rng(2026)
    n = 240
    p = rng.uniform(900, 2200, n)
    v = rng.uniform(20, 250, n)
    t = rng.uniform(293, 900, n)
    y = 0.25 + 0.2 * np.exp(-v / 60) * (1 - 0.3 * (p - 900) / 1300) + 0.03 * np.sin(t / 80) + rng.normal(0, 0.005, n)
    with open(path, "w") as f:
        f.write("hertz_pressure_MPa,sliding_velocity_m_per_min,temperature_K,cof\n")
        for row in zip(p, v, t, y):
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def load(path: Path, features, target):
    import csv
    with open(path) as f:
        rows = list(csv.DictReader(f))
    x = np.array([[float(r[c]) for c in features] for r in rows])
    y = np.array([float(r[target]) for r in rows])
    return x, y, rows


def with_folds(path: Path, out: Path, n: int) -> np.ndarray:
    ids = np.zeros(n, dtype=int)
    for k, (_, test) in enumerate(KFold(5, shuffle=True, random_state=0).split(np.arange(n))):
        ids[test] = k
    lines = path.read_text().splitlines()
    out.write_text("\n".join([lines[0] + ",fold"] + [l + f",{ids[i]}" for i, l in enumerate(lines[1:])]) + "\n")
    return ids


def sk_oof_r2(make, x, y, ids, seeds):
    scores = []
    for s in seeds:
        oof = np.zeros_like(y)
        for k in range(5):
            tr, te = ids != k, ids == k
            m = make(s, y[tr])
            m.fit(x[tr], y[tr])
            oof[te] = m.predict(x[te])
        scores.append(r2_score(y, oof))
    return float(np.mean(scores)), float(np.std(scores))


def greybox_oof_r2(bin_, data, features, target, family, flags, seeds, work):
    scores = []
    for s in seeds:
        cmd = [bin_, "fit", "--data", str(data), "--target", target, "--features", ",".join(features),
               "--fold-column", "fold", "--families", family, "--inner-folds", "2", "--bootstrap", "10",
               "--importance-repeats", "1", "--seed", str(s), "--out", str(work / "gb"), "--force", "--json"] + flags
        out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
        scores.append(json.loads(out)["families"][0]["held_out"]["metrics"]["r2"]["value"])
    return float(np.mean(scores)), float(np.std(scores))


def configs(quick):
    rf = [("random-forest", "n_estimators=100", ["--rf-n-estimators", "100"],
           lambda s, y: RandomForestRegressor(n_estimators=100, random_state=s), True)]
    svr = []
    for kernel, c, eps in [("rbf", 100, 0.01), ("poly", 10, 0.01), ("linear", 1, 0.01), ("sigmoid", 0.001, 0.01)]:
        svr.append(("svr", f"{kernel}, C={c}, eps={eps}",
                    ["--svr-kernel", kernel, "--svr-c", str(c), "--svr-epsilon", str(eps)],
                    (lambda k, c, e: lambda s, y: make_pipeline(StandardScaler(), SVR(kernel=k, C=c, epsilon=e, gamma="scale")))(kernel, c, eps),
                    False))
    gb = []
    for n, d, lr in [(500, 5, 0.1), (100, 3, 0.05)]:
        gb.append(("gradient-boosting", f"{n} trees, depth {d}, lr {lr}",
                   ["--gb-n-estimators", str(n), "--gb-max-depth", str(d), "--gb-learning-rate", str(lr)],
                   (lambda n, d, lr: lambda s, y: XGBRegressor(n_estimators=n, max_depth=d, learning_rate=lr, tree_method="exact",
                                                              reg_lambda=1.0, min_child_weight=1.0, base_score=float(np.mean(y)), n_jobs=1))(n, d, lr),
                   False))
    mlp = []
    for hidden, act, lr in [((32, 16), "relu", 0.01), ((64, 32), "tanh", 0.001)]:
        mlp.append(("mlp", f"{hidden}, {act}, lr {lr}",
                    ["--mlp-hidden", "x".join(map(str, hidden)), "--mlp-activation", act, "--mlp-learning-rate", str(lr)],
                    (lambda h, a, lr: lambda s, y: TransformedTargetRegressor(
                        regressor=make_pipeline(StandardScaler(), MLPRegressor(hidden_layer_sizes=h, activation=a, learning_rate_init=lr,
                                                                               early_stopping=True, validation_fraction=0.1, n_iter_no_change=10,
                                                                               tol=1e-4, max_iter=200, alpha=1e-4, random_state=s)),
                        transformer=StandardScaler()))(hidden, act, lr),
                    True))
    if quick:
        return [rf[0], svr[0], svr[1], gb[0], mlp[0]]
    return rf + svr + gb + mlp


def main():
    warnings.filterwarnings("ignore")  # sklearn ConvergenceWarning at max_iter, identical on our side
    ap = argparse.ArgumentParser()
    ap.add_argument("greybox")
    ap.add_argument("out")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--markdown")
    a = ap.parse_args()
    work = Path(a.out)
    work.mkdir(parents=True, exist_ok=True)
    subprocess.run([a.greybox, "demo", "--out", str(work / "demo")], check=True, capture_output=True)
    second_dataset(work / "second.csv")
    datasets = [
        ("example (demo)", work / "demo" / "dataset.csv", ["normal_force_N", "sliding_velocity_m_per_min"], "cof_apparent"),
        ("second (3 features)", work / "second.csv", ["hertz_pressure_MPa", "sliding_velocity_m_per_min", "temperature_K"], "cof"),
    ]
    if a.quick:
        datasets = datasets[:1]
    results = []
    for name, path, feats, target in datasets:
        x, y, _ = load(path, feats, target)
        data = work / (path.stem + "_folds.csv")
        ids = with_folds(path, data, len(y))
        for family, label, flags, make, stochastic in configs(a.quick):
            seeds = SEEDS if stochastic else SEEDS[:1]
            ref, ref_sd = sk_oof_r2(make, x, y, ids, seeds)
            ours, ours_sd = greybox_oof_r2(a.greybox, data, feats, target, family, flags, seeds, work)
            ok = abs(ours - ref) <= TOL
            results.append({"dataset": name, "family": family, "config": label, "seeds": len(seeds), "reference_r2": ref, "reference_sd": ref_sd,
                            "greybox_r2": ours, "greybox_sd": ours_sd, "diff": ours - ref, "pass": ok})
            print(f"{name:22s} {family:18s} {label:28s} ref {ref:8.4f}  greybox {ours:8.4f}  diff {ours - ref:+.4f}  {'ok' if ok else 'FAIL'}", flush=True)
    (work / "parity.json").write_text(json.dumps(results, indent=2))
    if a.markdown:
        lines = ["| dataset | family | hyperparameters | seeds | reference R² (sd over seeds) | greybox R² (sd) | Δ | within 0.01 |", "|---|---|---|---|---|---|---|---|"]
        for r in results:
            sd = lambda v: f" ({v:.3f})" if r["seeds"] > 1 else ""
            lines.append(f"| {r['dataset']} | {r['family']} | {r['config']} | {r['seeds']} | {r['reference_r2']:.4f}{sd(r['reference_sd'])} | "
                         f"{r['greybox_r2']:.4f}{sd(r['greybox_sd'])} | {r['diff']:+.4f} | {'yes' if r['pass'] else 'NO'} |")
        Path(a.markdown).write_text("\n".join(lines) + "\n")
    failed = [r for r in results if not r["pass"]]
    print(f"parity: {len(results) - len(failed)} passed, {len(failed)} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
