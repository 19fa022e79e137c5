"""ONNX models converted into greybox models agree with onnxruntime: tree splits exactly
(points on and around every threshold, float32 ties included), sums, networks and SVMs to
float32 rounding — and unsupported graphs are refused naming the operator."""

import numpy as np
import pytest

import greybox as gb
from conftest import FEATURES
from test_import_parity import f32_neighbourhood

onnx = pytest.importorskip("onnx")
ort = pytest.importorskip("onnxruntime")
skl2onnx = pytest.importorskip("skl2onnx")
from onnx import TensorProto, helper  # noqa: E402
from sklearn.ensemble import GradientBoostingRegressor, RandomForestRegressor  # noqa: E402
from sklearn.linear_model import LinearRegression  # noqa: E402
from sklearn.neural_network import MLPRegressor  # noqa: E402
from sklearn.pipeline import make_pipeline  # noqa: E402
from sklearn.preprocessing import StandardScaler  # noqa: E402
from sklearn.svm import SVR  # noqa: E402


def run_ort(model_bytes, X):
    s = ort.InferenceSession(model_bytes, providers=["CPUExecutionProvider"])
    name = s.get_inputs()[0].name
    return np.asarray(s.run(None, {name: X.astype(np.float32)})[0], dtype=np.float64).ravel()


def tree_threshold_points(model_bytes, queries):
    m = onnx.load_from_string(model_bytes)
    node = next(n for n in m.graph.node if n.op_type == "TreeEnsembleRegressor")
    a = {x.name: helper.get_attribute_value(x) for x in node.attribute}
    rng = np.random.default_rng(5)
    rows = [queries]
    for f in (0, 1):
        t = np.array([v for v, k, mode in zip(a["nodes_values"], a["nodes_featureids"], a["nodes_modes"]) if k == f and mode != b"LEAF"], dtype=np.float64)
        pts = f32_neighbourhood(np.unique(t))
        r = np.empty((len(pts), 2))
        r[:, f] = pts
        r[:, 1 - f] = queries[rng.integers(0, len(queries), len(pts)), 1 - f]
        rows.append(r)
    return np.vstack(rows)


SK = {
    "random-forest": lambda: RandomForestRegressor(n_estimators=20, random_state=0),
    "gradient-boosting": lambda: GradientBoostingRegressor(n_estimators=40, random_state=0),
    "mlp-relu": lambda: make_pipeline(StandardScaler(), MLPRegressor(hidden_layer_sizes=(16, 8), max_iter=300, random_state=0)),
    "mlp-tanh": lambda: make_pipeline(StandardScaler(), MLPRegressor(hidden_layer_sizes=(10,), activation="tanh", max_iter=300, random_state=0)),
    "mlp-logistic": lambda: make_pipeline(StandardScaler(), MLPRegressor(hidden_layer_sizes=(10,), activation="logistic", max_iter=300, random_state=0)),
    **{f"svr-{k}": (lambda k=k: make_pipeline(StandardScaler(), SVR(kernel=k, C=3.0, epsilon=0.01))) for k in ["linear", "poly", "rbf", "sigmoid"]},
    "linear": lambda: LinearRegression(),
}


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("name", SK)
def test_converted_sklearn_models_agree_with_onnxruntime(name, data, queries, tmp_path):
    X, y, _, _ = data
    est = SK[name]().fit(X, y)
    onx = skl2onnx.to_onnx(est, X[:1].astype(np.float32)).SerializeToString()
    P = tree_threshold_points(onx, queries) if "forest" in name or "boosting" in name else queries
    path = tmp_path / "m.onnx"
    path.write_bytes(onx)
    model = gb.from_onnx(path, features=FEATURES, X_train=X)
    if name in ("random-forest", "gradient-boosting"):
        # an average of trees is a forest, a sum of trees is boosting
        assert model.family == name
    ref = run_ort(onx, P)
    ours = model.predict(P).value
    # The runtime computes in float32: its error grows with the magnitude of the terms it
    # adds up (an SVR's Σ|cᵢ K(svᵢ, x)| can be 1000 × its result). Bound: 1e-6 of that sum,
    # computed here from the graph's own numbers; a wrong split would cost a whole leaf.
    terms = svr_terms(onx, P) if name.startswith("svr") else np.abs(ref)
    err = np.abs(ours - ref) / np.maximum(terms, 1e-2)
    assert np.max(err) < 2e-6 if name.startswith("svr") else np.max(err) < 2e-5, f"{name}: {np.max(err):.2e}"


def svr_terms(onx, P):
    """Σ|cᵢ K(svᵢ, z)| + |ρ| per point, in float64 from the graph's attributes."""
    m = onnx.load_from_string(onx)
    att = {n.op_type: {a.name: helper.get_attribute_value(a) for a in n.attribute} for n in m.graph.node}
    sc, sv = att["Scaler"], att["SVMRegressor"]
    Z = (P - np.array(sc["offset"])) * np.array(sc["scale"])
    S = np.array(sv["support_vectors"]).reshape(sv["n_supports"], -1)
    c = np.array(sv["coefficients"])
    g, c0, d = sv["kernel_params"]
    kind = sv["kernel_type"].decode()
    dot = Z @ S.T
    K = {"LINEAR": dot, "POLY": (g * dot + c0) ** d, "SIGMOID": np.tanh(g * dot + c0),
         "RBF": np.exp(-g * ((Z[:, None, :] - S[None, :, :]) ** 2).sum(-1))}[kind]
    return np.abs(K * c).sum(1) + abs(sv["rho"][0])


def hand_made_tree(mode_root, mode_child, aggregate):
    """Two stumps-with-a-child under the given modes, with a Div scaler in front."""
    node = helper.make_node(
        "TreeEnsembleRegressor", ["Z"], ["Y"], domain="ai.onnx.ml",
        nodes_treeids=[0, 0, 0, 0, 0, 1, 1, 1], nodes_nodeids=[0, 1, 2, 3, 4, 0, 1, 2],
        nodes_featureids=[0, 1, 0, 0, 0, 1, 0, 0],
        nodes_values=[0.3, 0.55, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0],
        nodes_modes=[mode_root, mode_child, "LEAF", "LEAF", "LEAF", mode_child, "LEAF", "LEAF"],
        nodes_truenodeids=[1, 3, 0, 0, 0, 1, 0, 0], nodes_falsenodeids=[2, 4, 0, 0, 0, 2, 0, 0],
        target_ids=[0] * 5, target_nodeids=[2, 3, 4, 1, 2], target_treeids=[0, 0, 0, 1, 1],
        target_weights=[0.5, -0.25, 0.125, 0.0625, -0.03125], base_values=[0.25],
        aggregate_function=aggregate, n_targets=1, post_transform="NONE",
    )
    scale = helper.make_tensor("s", TensorProto.FLOAT, [2], [3.0, 7.0])
    div = helper.make_node("Div", ["X", "s"], ["Z"])
    g = helper.make_graph([div, node], "g", [helper.make_tensor_value_info("X", TensorProto.FLOAT, [None, 2])],
                          [helper.make_tensor_value_info("Y", TensorProto.FLOAT, [None, 1])], [scale])
    return helper.make_model(g, opset_imports=[helper.make_opsetid("", 17), helper.make_opsetid("ai.onnx.ml", 3)])


@pytest.mark.parametrize("modes", [("BRANCH_LEQ", "BRANCH_LT"), ("BRANCH_GTE", "BRANCH_GT"), ("BRANCH_LT", "BRANCH_GTE")])
@pytest.mark.parametrize("aggregate", ["SUM", "AVERAGE"])
def test_every_order_split_mode_is_exact(modes, aggregate):
    m = hand_made_tree(*modes, aggregate)
    # thresholds in raw units: 0.3·3, 0.55·7, 0.1·7 — and float32 neighbourhoods of each
    t = np.array([0.9, 3.85, 0.7])
    pts = f32_neighbourhood(np.concatenate([t, t * np.float32(1.0)]))
    P = np.column_stack([np.tile(pts, len(pts)), np.repeat(pts, len(pts))])
    ref = run_ort(m.SerializeToString(), P)
    ours = gb.from_onnx(m, features=FEATURES, domain=[(0, 10), (0, 10)]).predict(P).value
    # leaves are binary fractions: the float32 sums are exact, so the agreement is exact
    np.testing.assert_array_equal(ours, ref)


def test_a_gemm_network_with_sigmoid_and_scaling():
    rng = np.random.default_rng(2)
    W1, b1 = rng.normal(size=(5, 2)).astype(np.float32), rng.normal(size=5).astype(np.float32)
    W2, b2 = rng.normal(size=(1, 5)).astype(np.float32), rng.normal(size=1).astype(np.float32)
    inits = [helper.make_tensor("m", TensorProto.FLOAT, [2], [1000.0, 100.0]),
             helper.make_tensor("d", TensorProto.FLOAT, [2], [500.0, 60.0]),
             helper.make_tensor("W1", TensorProto.FLOAT, [5, 2], W1.ravel()), helper.make_tensor("b1", TensorProto.FLOAT, [5], b1),
             helper.make_tensor("W2", TensorProto.FLOAT, [1, 5], W2.ravel()), helper.make_tensor("b2", TensorProto.FLOAT, [1], b2)]
    nodes = [helper.make_node("Sub", ["X", "m"], ["a"]), helper.make_node("Div", ["a", "d"], ["z"]),
             helper.make_node("Gemm", ["z", "W1", "b1"], ["h"], transB=1), helper.make_node("Sigmoid", ["h"], ["s"]),
             helper.make_node("Gemm", ["s", "W2", "b2"], ["Y"], transB=1, alpha=0.5, beta=2.0)]
    g = helper.make_graph(nodes, "g", [helper.make_tensor_value_info("X", TensorProto.FLOAT, [None, 2])],
                          [helper.make_tensor_value_info("Y", TensorProto.FLOAT, [None, 1])], inits)
    m = helper.make_model(g, opset_imports=[helper.make_opsetid("", 17)])
    X = np.column_stack([rng.uniform(150, 2000, 500), rng.uniform(20, 250, 500)])
    ours = gb.from_onnx(m.SerializeToString(), features=FEATURES, domain=[(150, 2000), (20, 250)]).predict(X).value
    ref = run_ort(m.SerializeToString(), X)
    assert np.max(np.abs(ours - ref) / np.maximum(np.abs(ref), 1e-2)) < 2e-5


def test_unsupported_operators_are_named(data):
    from sklearn.neighbors import KNeighborsRegressor

    X, y, _, _ = data
    onx = skl2onnx.to_onnx(KNeighborsRegressor().fit(X, y), X[:1].astype(np.float32))
    with pytest.raises(gb.GreyboxError, match="is not supported"):
        gb.from_onnx(onx, features=FEATURES, X_train=X)
    with pytest.raises(gb.GreyboxError, match="not an ONNX model"):
        gb.from_onnx(b"\x08\x07garbage", features=FEATURES, X_train=X)
