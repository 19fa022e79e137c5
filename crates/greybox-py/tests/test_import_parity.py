"""Imported models predict as the library that trained them: trees to 1e-12 relative (splits
bit-exact, including points exactly on thresholds and on float32 rounding ties), XGBoost bit
for bit, SVR and MLP to 1e-9 relative — on thousands of points, against the real libraries."""

import numpy as np
import pytest

import greybox as gb
from conftest import DOMAIN, FEATURES

# The query points reach 10 % beyond the training domain on purpose (parity holds there too).
pytestmark = pytest.mark.filterwarnings("ignore::greybox.DomainWarning")

sklearn = pytest.importorskip("sklearn")
from sklearn.ensemble import (  # noqa: E402
    ExtraTreesRegressor,
    GradientBoostingRegressor,
    HistGradientBoostingRegressor,
    RandomForestRegressor,
)
from sklearn.neural_network import MLPRegressor  # noqa: E402
from sklearn.pipeline import make_pipeline  # noqa: E402
from sklearn.preprocessing import MinMaxScaler, StandardScaler  # noqa: E402
from sklearn.svm import SVR  # noqa: E402


def f32_neighbourhood(t):
    """Points at and around a threshold t: t itself, its f64 neighbours, the float32 values
    nearest t and the exact midpoints between them (ties of the float32 cast)."""
    t = np.asarray(t, dtype=np.float64)
    t32 = t.astype(np.float32)
    below = np.nextafter(t32, np.float32(-np.inf))
    above = np.nextafter(t32, np.float32(np.inf))
    pts = [
        t,
        np.nextafter(t, -np.inf),
        np.nextafter(t, np.inf),
        t32.astype(np.float64),
        below.astype(np.float64),
        above.astype(np.float64),
        (t32.astype(np.float64) + below.astype(np.float64)) / 2,
        (t32.astype(np.float64) + above.astype(np.float64)) / 2,
    ]
    return np.concatenate(pts)


def threshold_points(thresholds_per_feature, queries, scalers=()):
    """Rows where one feature sits on (or around) a split threshold, the other random.
    With scalers in front, thresholds are mapped back to raw units first."""
    rng = np.random.default_rng(3)
    rows = []
    for f, ts in enumerate(thresholds_per_feature):
        ts = np.asarray(sorted(set(ts)), dtype=np.float64)
        if len(ts) == 0:
            continue
        for s in reversed(scalers):
            ts = s.inverse_transform(np.column_stack([ts if k == f else np.zeros_like(ts) for k in range(2)]))[:, f]
        pts = f32_neighbourhood(ts)
        other = queries[rng.integers(0, len(queries), len(pts)), 1 - f]
        r = np.empty((len(pts), 2))
        r[:, f] = pts
        r[:, 1 - f] = other
        rows.append(r)
    return np.vstack(rows + [queries])


class HistTree:
    """A histogram-boosting predictor's nodes seen as a tree_ (feature −2 at leaves)."""

    def __init__(self, nodes):
        self.feature = np.where(nodes["is_leaf"].astype(bool), -2, nodes["feature_idx"])
        self.threshold = nodes["num_threshold"]


def sklearn_thresholds(trees):
    ts = [[], []]
    for t in trees:
        for feat, thr in zip(t.feature, t.threshold):
            if feat >= 0:
                ts[feat].append(thr)
    return ts


def assert_close(ours, ref, rtol, what):
    scale = np.maximum(np.abs(ref), 1e-3)
    err = np.max(np.abs(ours - ref) / scale)
    assert err <= rtol, f"{what}: max relative deviation {err:.3e} > {rtol:.0e}"


TREE_MODELS = {
    "random-forest": lambda: RandomForestRegressor(n_estimators=25, random_state=0),
    "extra-trees": lambda: ExtraTreesRegressor(n_estimators=25, random_state=0),
    "gradient-boosting": lambda: GradientBoostingRegressor(n_estimators=60, max_depth=3, random_state=0),
    "hist-gradient-boosting": lambda: HistGradientBoostingRegressor(max_iter=60, random_state=0),
    "hist-boosting-behind-standard-scaler": lambda: make_pipeline(StandardScaler(), HistGradientBoostingRegressor(max_iter=30, loss="absolute_error", random_state=0)),
    "forest-behind-standard-scaler": lambda: make_pipeline(StandardScaler(), RandomForestRegressor(n_estimators=15, random_state=0)),
    "boosting-behind-minmax-scaler": lambda: make_pipeline(MinMaxScaler(), GradientBoostingRegressor(n_estimators=30, random_state=0)),
    "forest-behind-two-scalers": lambda: make_pipeline(MinMaxScaler(clip=True), StandardScaler(), ExtraTreesRegressor(n_estimators=10, random_state=0)),
}


@pytest.mark.parametrize("name", TREE_MODELS)
def test_sklearn_trees_agree_on_and_around_every_threshold(name, data, queries):
    X, y, _, _ = data
    est = TREE_MODELS[name]().fit(X, y)
    reg = est[-1] if hasattr(est, "steps") else est
    scalers = [s for _, s in est.steps[:-1]] if hasattr(est, "steps") else []
    if isinstance(reg, HistGradientBoostingRegressor):
        trees = [HistTree(it[0].nodes) for it in reg._predictors]
    else:
        trees = [e.tree_ for e in np.ravel(reg.estimators_)]
    P = threshold_points(sklearn_thresholds(trees), queries, scalers)
    model = gb.from_sklearn(est, features=FEATURES, X_train=X)
    ours = model.predict(P).value
    assert_close(ours, est.predict(P), 1e-12, name)
    assert len(P) > 3000


SMOOTH_MODELS = {
    **{f"svr-{k}": (lambda k=k: make_pipeline(StandardScaler(), SVR(kernel=k, C=3.0, epsilon=0.01))) for k in ["linear", "poly", "rbf", "sigmoid"]},
    "svr-rbf-minmax": lambda: make_pipeline(MinMaxScaler(), SVR(C=10.0, epsilon=0.005, gamma=2.0)),
    "svr-rbf-two-scalers": lambda: make_pipeline(MinMaxScaler(), StandardScaler(), SVR(C=10.0)),
    **{f"mlp-{a}": (lambda a=a: make_pipeline(StandardScaler(), MLPRegressor(hidden_layer_sizes=(16, 8), activation=a, max_iter=300, random_state=0))) for a in ["relu", "tanh", "logistic", "identity"]},
    "mlp-minmax": lambda: make_pipeline(MinMaxScaler(), MLPRegressor(hidden_layer_sizes=(12,), max_iter=300, random_state=1)),
}


@pytest.mark.filterwarnings("ignore::sklearn.exceptions.ConvergenceWarning")
@pytest.mark.parametrize("name", SMOOTH_MODELS)
def test_sklearn_svr_and_mlp_agree_to_1e9(name, data, queries):
    X, y, _, _ = data
    est = SMOOTH_MODELS[name]().fit(X, y)
    model = gb.from_sklearn(est, features=FEATURES, X_train=X)
    assert_close(model.predict(queries).value, est.predict(queries), 1e-9, name)


@pytest.fixture(scope="module")
def xgb_model(data):
    xgb = pytest.importorskip("xgboost")
    X, y, _, _ = data
    return xgb.XGBRegressor(n_estimators=80, max_depth=5, learning_rate=0.2, random_state=0).fit(X, y)


def xgboost_thresholds(booster):
    import json

    ts = [[], []]
    for tree in json.loads(booster.save_raw("json"))["learner"]["gradient_booster"]["model"]["trees"]:
        for left, f, s in zip(tree["left_children"], tree["split_indices"], tree["split_conditions"]):
            if left != -1:
                ts[f].append(s)
    return ts


@pytest.mark.parametrize("fmt", ["json", "ubj"])
def test_xgboost_agrees_bit_for_bit(fmt, xgb_model, data, queries, tmp_path):
    X = data[0]
    path = tmp_path / f"booster.{fmt}"
    xgb_model.get_booster().save_model(path)
    P = threshold_points(xgboost_thresholds(xgb_model.get_booster()), queries)
    model = gb.from_xgboost(path, features=FEATURES, X_train=X)
    ref = xgb_model.predict(P).astype(np.float64)
    ours = model.predict(P).value
    assert np.array_equal(ours, ref), f"{np.count_nonzero(ours != ref)} of {len(P)} differ"


def test_xgboost_from_the_estimator_object(xgb_model, data, queries):
    model = gb.from_xgboost(xgb_model, features=FEATURES, domain=DOMAIN)
    assert np.array_equal(model.predict(queries).value, xgb_model.predict(queries).astype(np.float64))
    assert model.hyperparameters["library"].startswith("xgboost ")
    assert model.training_domain == DOMAIN


def test_calibration_rows_give_a_split_conformal_interval(data):
    X, y, Xc, yc = data
    est = RandomForestRegressor(n_estimators=20, random_state=0).fit(X, y)
    model = gb.from_sklearn(est, features=FEATURES, X_train=X, X_cal=Xc, y_cal=yc, coverage=0.9)
    iv = model.interval
    assert iv["method"] == "split-conformal" and iv["coverage"] == 0.9
    r = np.sort(np.abs(yc - est.predict(Xc)))
    k = int(np.ceil((len(yc) + 1) * 0.9))
    assert iv["half_width"] == pytest.approx(r[k - 1], rel=1e-12)
    assert 0.0 < model.held_out_r2 <= 1.0
    bare = gb.from_sklearn(est, features=FEATURES, X_train=X)
    assert bare.interval["method"] == "none" and bare.interval["half_width"] == 0.0


def test_imported_model_is_a_friction_law_and_saves(data, tmp_path):
    X, y, _, _ = data
    est = make_pipeline(StandardScaler(), SVR(C=3.0, epsilon=0.01)).fit(X, y)
    model = gb.from_sklearn(est, features=["normal_force_N", "sliding_velocity_m_per_s"], domain=[(150, 2000), (0.3, 4.2)])
    path = tmp_path / "imported.json"
    model.save(path)
    back = gb.load_model(path)
    assert back.content_hash == model.content_hash
    # A model on normal force needs the contact's Hertz map: the law says so, naming the way out.
    with pytest.raises(gb.GreyboxError, match="imported without a contact"):
        back.law()


def test_an_export_file_imports_like_the_estimator(data, queries, tmp_path):
    import json

    X, y, _, _ = data
    est = make_pipeline(MinMaxScaler(), GradientBoostingRegressor(n_estimators=20, random_state=0)).fit(X, y)
    path = tmp_path / "export.json"
    path.write_text(json.dumps(gb.export_sklearn(est)))
    from_file = gb.import_model(path, features=FEATURES, domain=DOMAIN)
    direct = gb.from_sklearn(est, features=FEATURES, domain=DOMAIN)
    np.testing.assert_array_equal(from_file.predict(queries).value, direct.predict(queries).value)
    assert "export.json (sha256 " in from_file.hyperparameters["source"]


def test_python_and_the_command_line_report_the_same_error(tmp_path):
    import os
    import subprocess

    from conftest import GREYBOX_CLI as cli

    if cli is None:
        pytest.skip("the greybox binary is not built (cargo build --release -p greybox-cli)")
    bad = tmp_path / "bad.json"
    bad.write_text('{"hello": 1}')
    r = subprocess.run([cli, "import", str(bad), "--domain", "0:1,0:1", "--out", str(tmp_path / "m.json")], capture_output=True, text=True)
    cli_message = r.stderr.strip().removeprefix("error: ")
    with pytest.raises(gb.GreyboxError) as e:
        gb.import_model(bad, domain=[(0, 1), (0, 1)])
    assert str(e.value) == cli_message


def test_unsupported_models_and_bad_inputs_are_clear_errors(data):
    from sklearn.linear_model import LinearRegression

    X, y, _, _ = data
    with pytest.raises(ValueError, match="LinearRegression is not supported"):
        gb.from_sklearn(LinearRegression().fit(X, y), features=FEATURES, X_train=X)
    est = RandomForestRegressor(n_estimators=3, random_state=0).fit(X, y)
    with pytest.raises(gb.GreyboxError, match="3 names for a model of 2 features"):
        gb.from_sklearn(est, features=FEATURES + ["x_K"], X_train=X)
    with pytest.raises(gb.GreyboxError, match="state the training domain"):
        gb.from_sklearn(est, features=FEATURES)
    with pytest.raises(gb.GreyboxError, match="records no feature names"):
        gb.from_sklearn(est, X_train=X)


def test_imported_trees_give_exact_tables_and_engine_exports(tmp_path):
    """An XGBoost model on (pressure, sliding velocity) becomes a law whose surrogate table and
    Abaqus table hold it exactly: deviation 0, and the table as a law gives the booster's
    own predictions bit for bit."""
    xgb = pytest.importorskip("xgboost")
    rng = np.random.default_rng(4)
    X = np.column_stack([rng.uniform(800, 2400, 400), rng.uniform(0.5, 4.0, 400)])  # MPa, m/s
    y = 0.5 - 1e-4 * X[:, 0] - 0.03 * X[:, 1] + rng.normal(0, 0.01, 400)
    booster = xgb.XGBRegressor(n_estimators=40, max_depth=4).fit(X, y)
    model = gb.from_xgboost(booster, features=["contact_pressure_MPa", "sliding_velocity_m_per_s"], X_train=X)
    model.save(tmp_path / "model.json")
    p = np.linspace(800e6, 2400e6, 9)
    v = np.linspace(0.5, 4.0, 8)
    table = gb.export_table(tmp_path / "model.json", "table", tmp_path / "table.json", p, v)
    assert table["max_deviation"] == 0.0 and table["exact_steps"]
    abaqus = gb.export_table(tmp_path / "model.json", "abaqus", tmp_path / "friction.inp", p, v)
    assert abaqus["max_deviation"] == 0.0
    Q = np.column_stack([rng.uniform(800, 2400, 2000), rng.uniform(0.5, 4.0, 2000)])
    mu = gb.load_law(tmp_path / "table.json").mu(Q[:, 0] * 1e6, Q[:, 1]).mu
    np.testing.assert_array_equal(mu, booster.predict(Q).astype(np.float64))
