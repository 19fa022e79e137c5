#!/usr/bin/env python3
"""The article's learning protocol done by the Python reference stack (scikit-learn 1.9 and
xgboost 3.2), timed end to end, for comparison with `greybox fit` on the same data:

for each family: GridSearchCV (5-fold, MSE) over the article's grid → refit → training metrics
with 1000 bootstrap CIs → nested CV (the same grid search inside 5 outer folds) → permutation
importance (30 repeats, seed 42, R²) → conformal half-width from the CV residuals.
Both sides use both cores (n_jobs=-1 here, rayon in greybox). Also single-point prediction
latency (model.predict on one row).

Usage: bench_learn.py DATASET.csv OUT.json
"""
import json
import sys
import time
import warnings

import numpy as np
from sklearn.compose import TransformedTargetRegressor
from sklearn.ensemble import RandomForestRegressor
from sklearn.inspection import permutation_importance
from sklearn.model_selection import GridSearchCV, KFold, cross_val_predict
from sklearn.neural_network import MLPRegressor
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVR
from xgboost import XGBRegressor

warnings.filterwarnings("ignore")
FEATURES = ["normal_force_N", "sliding_velocity_m_per_min"]
TARGET = "cof_apparent"


def load(path):
    import csv
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return np.array([[float(r[c]) for c in FEATURES] for r in rows]), np.array([float(r[TARGET]) for r in rows])


def families():
    mlp = TransformedTargetRegressor(
        regressor=Pipeline([("s", StandardScaler()), ("m", MLPRegressor(early_stopping=True, max_iter=200, random_state=0))]),
        transformer=StandardScaler())
    return {
        "random-forest": (RandomForestRegressor(random_state=0), {"n_estimators": [10, 50, 100, 200]}),
        "svr": (Pipeline([("s", StandardScaler()), ("m", SVR())]),
                {"m__C": [0.1, 1, 10, 100], "m__kernel": ["linear", "poly", "rbf", "sigmoid"], "m__epsilon": [0.01, 0.1, 0.2, 0.5]}),
        "gradient-boosting": (XGBRegressor(tree_method="exact", n_jobs=1),
                              {"n_estimators": [100, 300, 500], "max_depth": [3, 5, 7], "learning_rate": [0.01, 0.05, 0.1]}),
        "mlp": (mlp, {"regressor__m__hidden_layer_sizes": [(64, 32), (32, 16)], "regressor__m__activation": ["relu", "tanh"],
                      "regressor__m__learning_rate_init": [0.001, 0.01, 0.1]}),
    }


def bootstrap(y, p, rng, n=1000):
    idx = rng.integers(0, len(y), (n, len(y)))
    yb, pb = y[idx], p[idx]
    out = {}
    for name, f in {"mae": lambda a, b: np.abs(a - b).mean(1), "mse": lambda a, b: ((a - b) ** 2).mean(1),
                    "mape": lambda a, b: (np.abs(a - b) / np.abs(a)).mean(1)}.items():
        s = f(yb, pb)
        out[name] = [float(np.percentile(s, 2.5)), float(np.percentile(s, 97.5))]
    return out


def main(path, out):
    x, y = load(path)
    cv = KFold(5, shuffle=True, random_state=42)
    result = {"families": {}}
    t_all = time.perf_counter()
    for name, (est, grid) in families().items():
        t0 = time.perf_counter()
        gs = GridSearchCV(est, grid, cv=cv, scoring="neg_mean_squared_error", n_jobs=-1).fit(x, y)
        best = gs.best_estimator_
        pred = best.predict(x)
        ci = bootstrap(y, pred, np.random.default_rng(42))
        nested = GridSearchCV(est, grid, cv=KFold(5, shuffle=True, random_state=7), scoring="neg_mean_squared_error", n_jobs=-1)
        oof = cross_val_predict(nested, x, y, cv=cv)
        ci_held = bootstrap(y, oof, np.random.default_rng(43))
        imp = permutation_importance(best, x, y, n_repeats=30, random_state=42, scoring="r2", n_jobs=-1)
        resid = np.sort(np.abs(y - cross_val_predict(best, x, y, cv=cv)))
        q = resid[min(len(y), int(np.ceil((len(y) + 1) * 0.95))) - 1]
        seconds = time.perf_counter() - t0
        row = x[:1]
        best.predict(row)
        n = 2000
        t1 = time.perf_counter()
        for _ in range(n):
            best.predict(row)
        latency_us = (time.perf_counter() - t1) / n * 1e6
        result["families"][name] = {"seconds": seconds, "selected": str(gs.best_params_), "single_point_us": latency_us,
                                    "importance": imp.importances_mean.tolist(), "half_width": float(q),
                                    "training_ci": ci, "held_out_ci": ci_held}
        print(f"{name}: {seconds:.1f} s, single point {latency_us:.0f} us, selected {gs.best_params_}", flush=True)
    result["total_seconds"] = time.perf_counter() - t_all
    print(f"total: {result['total_seconds']:.1f} s")
    with open(out, "w") as f:
        json.dump(result, f, indent=2)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
