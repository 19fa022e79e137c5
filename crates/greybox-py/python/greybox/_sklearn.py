"""scikit-learn estimators as greybox-sklearn JSON documents.

The fitted attributes are copied untouched (floats through ``float.__repr__``, which round-trips
exactly); the Rust side (``greybox-import``) restates the trees' float32 splits on the raw
input and folds the scalers, so that the imported model predicts as scikit-learn does.
"""

from __future__ import annotations

import json
from typing import Any

SCHEMA = "greybox-sklearn"
SCHEMA_VERSION = 1


def _floats(a: Any) -> list:
    import numpy as np

    return np.asarray(a, dtype=np.float64).tolist()


def _tree(t: Any) -> dict:
    """One fitted ``tree_`` (regression, one output) as parallel arrays."""
    if t.n_outputs != 1:
        raise ValueError(f"a tree with {t.n_outputs} outputs: only single-output regression is supported")
    return {
        "children_left": t.children_left.tolist(),
        "children_right": t.children_right.tolist(),
        "feature": t.feature.tolist(),
        "threshold": _floats(t.threshold),
        "value": _floats(t.value[:, 0, 0]),
    }


def _scaler(step: Any, n: int) -> dict:
    from sklearn.preprocessing import MinMaxScaler, StandardScaler

    import numpy as np

    if isinstance(step, StandardScaler):
        mean = step.mean_ if step.with_mean else np.zeros(n)
        scale = step.scale_ if (step.with_std and step.scale_ is not None) else np.ones(n)
        return {"kind": "standard_scaler", "mean": _floats(mean), "scale": _floats(scale)}
    if isinstance(step, MinMaxScaler):
        out = {"kind": "min_max_scaler", "scale": _floats(step.scale_), "min": _floats(step.min_)}
        if step.clip:
            out["clip"] = [float(step.feature_range[0]), float(step.feature_range[1])]
        return out
    raise ValueError(
        f"pipeline step {type(step).__name__}: only StandardScaler and MinMaxScaler may precede the regressor"
    )


def _gb_init(est: Any) -> float:
    from sklearn.dummy import DummyRegressor

    if est.init_ == "zero":
        return 0.0
    if isinstance(est.init_, DummyRegressor):
        return float(est.init_.constant_.ravel()[0])
    raise ValueError(
        f"GradientBoostingRegressor with init={type(est.init_).__name__}: only the default (a constant) or 'zero' is supported"
    )


def _hist_gradient_boosting(est: Any) -> dict:
    """The predictors of a HistGradientBoostingRegressor: leaves carry their learning-rate-scaled
    values; splits compare the float64 input (``X <= num_threshold``)."""
    import numpy as np

    if est.loss not in ("squared_error", "absolute_error", "quantile"):
        raise ValueError(
            f"HistGradientBoostingRegressor with loss={est.loss!r}: only losses predicting the raw sum (squared_error, absolute_error, quantile) are supported"
        )
    trees = []
    for it in est._predictors:
        if len(it) != 1:
            raise ValueError("a HistGradientBoostingRegressor with several trees per iteration is not supported")
        nodes = it[0].nodes
        if np.any(nodes["is_categorical"]):
            raise ValueError("HistGradientBoostingRegressor with categorical splits is not supported")
        leaf = nodes["is_leaf"].astype(bool)
        trees.append({
            "children_left": np.where(leaf, -1, nodes["left"].astype(np.int64)).tolist(),
            "children_right": np.where(leaf, -1, nodes["right"].astype(np.int64)).tolist(),
            "feature": nodes["feature_idx"].astype(np.int64).tolist(),
            "threshold": _floats(nodes["num_threshold"]),
            "value": _floats(nodes["value"]),
        })
    return {"kind": "hist_gradient_boosting", "init": float(np.ravel(est._baseline_prediction)[0]), "trees": trees}


def _regressor(est: Any) -> dict:
    from sklearn.ensemble import (
        ExtraTreesRegressor,
        GradientBoostingRegressor,
        HistGradientBoostingRegressor,
        RandomForestRegressor,
    )
    from sklearn.neural_network import MLPRegressor
    from sklearn.svm import SVR

    if isinstance(est, (RandomForestRegressor, ExtraTreesRegressor)):
        return {"kind": "forest", "trees": [_tree(e.tree_) for e in est.estimators_]}
    if isinstance(est, GradientBoostingRegressor):
        return {
            "kind": "gradient_boosting",
            "init": _gb_init(est),
            "learning_rate": float(est.learning_rate),
            "trees": [_tree(e.tree_) for e in est.estimators_[:, 0]],
        }
    if isinstance(est, HistGradientBoostingRegressor):
        return _hist_gradient_boosting(est)
    if isinstance(est, SVR):
        if not isinstance(est.kernel, str):
            raise ValueError("SVR with a callable kernel is not supported")
        return {
            "kind": "svr",
            "kernel": est.kernel,
            "gamma": float(est._gamma),
            "degree": int(est.degree),
            "coef0": float(est.coef0),
            "support_vectors": _floats(est.support_vectors_),
            "dual_coef": _floats(est.dual_coef_[0]),
            "intercept": float(est.intercept_[0]),
        }
    if isinstance(est, MLPRegressor):
        if est.n_outputs_ != 1:
            raise ValueError(f"an MLPRegressor with {est.n_outputs_} outputs: only one is supported")
        return {
            "kind": "mlp",
            "activation": est.activation,
            "coefs": [_floats(c) for c in est.coefs_],
            "intercepts": [_floats(b) for b in est.intercepts_],
        }
    raise ValueError(
        f"{type(est).__name__} is not supported: RandomForestRegressor, ExtraTreesRegressor, "
        "GradientBoostingRegressor, HistGradientBoostingRegressor, SVR and MLPRegressor are (optionally in a Pipeline behind "
        "StandardScaler/MinMaxScaler); convert other models to ONNX or retrain them with greybox"
    )


def export_sklearn(estimator: Any) -> dict:
    """The greybox-sklearn document of a fitted estimator or Pipeline (a JSON-ready dict)."""
    import sklearn
    from sklearn.pipeline import Pipeline

    steps = list(estimator.steps) if isinstance(estimator, Pipeline) else [("model", estimator)]
    steps = [(name, s) for name, s in steps if s not in (None, "passthrough")]
    if not steps:
        raise ValueError("the pipeline has no regressor")
    *pre, (_, reg) = steps
    n = getattr(estimator, "n_features_in_", None) or getattr(reg, "n_features_in_", None)
    if n is None:
        raise ValueError("the estimator is not fitted (no n_features_in_)")
    names = getattr(estimator, "feature_names_in_", None)
    label = type(reg).__name__
    if pre:
        label = f"Pipeline({', '.join(type(s).__name__ for _, s in pre)}, {label})"
    return {
        "schema": SCHEMA,
        "schema_version": SCHEMA_VERSION,
        "library_version": sklearn.__version__,
        "estimator": label,
        "n_features": int(n),
        "feature_names": None if names is None else [str(x) for x in names],
        "scalers": [_scaler(s, int(n)) for _, s in pre],
        "model": _regressor(reg),
    }


def export_sklearn_json(estimator: Any) -> str:
    """:func:`export_sklearn` as JSON text."""
    return json.dumps(export_sklearn(estimator), allow_nan=False)
