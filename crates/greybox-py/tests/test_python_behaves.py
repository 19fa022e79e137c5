"""The package behaves like a Python library: Ctrl-C stops a long call, every bad argument
is a GreyboxError naming it, NumPy arrays type-check where arrays are taken, and models and
laws pickle."""

import json
import os
import pickle
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest
from sklearn.ensemble import RandomForestRegressor

import greybox as gb

REPO = os.path.join(os.path.dirname(__file__), "..", "..", "..")


@pytest.fixture(scope="module")
def adhesive(tmp_path_factory):
    """A small identified, ploughing-corrected campaign (4 × 4) to fit on."""
    d = tmp_path_factory.mktemp("behaves")
    (d / "study.toml").write_text(gb.example("demo-study.toml"))
    gb.synth(d / "recordings", study=d / "study.toml", normal_force_count=4, velocity_count=4)
    gb.identify([d / "recordings"], d / "dataset.csv", study=d / "study.toml", normal_force_count=4, velocity_count=4)
    gb.ploughing_correction(d / "dataset.csv", d / "adhesive.csv")
    return d / "adhesive.csv"


@pytest.fixture(scope="module")
def model(adhesive, tmp_path_factory):
    out = tmp_path_factory.mktemp("fit") / "fit"
    gb.fit(adhesive, out, families=["svr", "random-forest"], skip_nested=True, folds=4, bootstrap=10, importance_repeats=2)
    return gb.load_model(out / "models" / "svr.json"), gb.load_model(out / "models" / "random-forest.json")


def interrupted_after(seconds, call):
    """Run `call` with a SIGINT to this process after `seconds`: (raised exception, seconds
    the call took)."""
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        call()
    except BaseException as e:  # noqa: B036 - the KeyboardInterrupt is the point
        return e, time.perf_counter() - start
    finally:
        timer.cancel()
    return None, time.perf_counter() - start


def test_ctrl_c_stops_a_cut_and_leaves_no_output(tmp_path):
    # the example cut at full resolution: minutes of work
    setup = os.path.join(REPO, "examples", "aisi1045-cut.toml")
    e, took = interrupted_after(0.5, lambda: gb.simulate_cut(setup, tmp_path / "cut"))
    assert isinstance(e, KeyboardInterrupt), e
    assert took < 5.0, took
    assert os.listdir(tmp_path) == [], os.listdir(tmp_path)  # no half-written output
    # the next call runs (the stop was that call's own)
    small = tmp_path / "small.toml"
    text = open(setup).read().replace("spacing_m = 1.0e-5", "spacing_m = 2.5e-5").replace("cut_length_m = 1.0e-3", "cut_length_m = 2.0e-5")
    small.write_text(text)
    assert gb.simulate_cut(small, tmp_path / "cut", as_frame=False)["steps"] > 0


def test_ctrl_c_stops_a_fit_and_leaves_no_output(adhesive, tmp_path):
    # a grid far too big to finish in the test (hundreds of MLP trainings)
    grid = dict(families=["mlp"], folds=4, inner_folds=3, mlp_hidden=["128x128"] * 4,
                mlp_learning_rate=[0.001 * (i + 1) for i in range(20)])
    e, took = interrupted_after(0.5, lambda: gb.fit(adhesive, tmp_path / "fit", **grid))
    assert isinstance(e, KeyboardInterrupt), e
    assert took < 5.0, took
    assert os.listdir(tmp_path) == [], os.listdir(tmp_path)


def _bad_calls(tmp_path, model):
    """(call, the argument its error must name)."""
    m = model[0]
    p, v = np.array([1e9, 2e9]), np.array([1.0, 2.0])
    return [
        (lambda: gb.hertz([100.0], radius_mm="17"), "radius_mm"),
        (lambda: gb.hertz("heavy"), "normal_force_N"),
        (lambda: gb.hertz([100.0], e1_GPa="stiff"), "e1_GPa"),
        (lambda: gb.synth(tmp_path / "s", normal_force_count=-1), "normal_force_count"),
        (lambda: gb.synth(3.5), "out"),
        (lambda: gb.synth(tmp_path / "s", format="xml"), "format"),
        (lambda: gb.read_recording(None), "path"),
        (lambda: gb.identify([tmp_path], tmp_path / "d.csv", velocity_count=-2), "velocity_count"),
        (lambda: gb.identify([tmp_path], tmp_path / "d.csv", track_radii_mm=["wide"]), "track_radii_mm"),
        (lambda: gb.identify([tmp_path], tmp_path / "d.csv", steady=5), "steady"),
        (lambda: gb.read_dataset(7), "path"),
        (lambda: gb.ploughing_correction("a.csv", "b.csv", pin_radius_mm="big"), "pin_radius_mm"),
        (lambda: gb.fit("a.csv", tmp_path / "f", features=3), "features"),
        (lambda: gb.fit("a.csv", tmp_path / "f", force="yes"), "force"),
        (lambda: gb.load_model(None), "path"),
        (lambda: gb.load_law(1), "path"),
        (lambda: gb.grey_box_law("m.json", "l.json", blend_fraction="x"), "blend_fraction"),
        (lambda: gb.grey_box_law("m.json", "l.json", mu_min="low"), "mu_min"),
        (lambda: gb.export_table("l.json", "csv", "o.csv", p, v, check_points=-5), "check_points"),
        (lambda: gb.export_table("l.json", "csv", "o.csv", "x", v), "pressure_Pa"),
        (lambda: gb.export_table("l.json", "csv", "o.csv", p, v, tolerance="tight"), "tolerance"),
        (lambda: gb.simulate_cut("c.toml", tmp_path / "c", fraction="half"), "fraction"),
        (lambda: gb.simulate_cut("c.toml", tmp_path / "c", frames=-1), "frames"),
        (lambda: gb.report(2.0), "study_dir"),
        (lambda: gb.import_model("x.json", coverage="most", domain=[(0, 1), (0, 1)]), "coverage"),
        (lambda: gb.from_xgboost("x.json", coverage="most", domain=[(0, 1), (0, 1)]), "coverage"),
        (lambda: m.predict([[100.0, 50.0]], margin="wide"), "margin"),
        (lambda: m.predict("rows"), "X"),
        (lambda: m.mu(p, v, outside=1), "outside"),
        (lambda: m.mu(["high"], v), "pressure_Pa"),
        (lambda: m.save(None), "path"),
        (lambda: m.law().mu(p, {"a": 1}), "velocity_m_per_s"),
        (lambda: gb.Model.from_json(12), "text"),
        (lambda: gb.grey_box_law("m.json", "l.json", blend_fraction=float("nan")), "blend_fraction"),
        (lambda: gb.grey_box_law("m.json", "l.json", mu_max=float("inf")), "mu_max"),
        (lambda: gb.from_sklearn(RandomForestRegressor(), features=["pressure_Pa", "velocity_m_per_s"]), "estimator"),
        (lambda: gb.from_sklearn("a regressor", features=["pressure_Pa", "velocity_m_per_s"]), "estimator"),
        (lambda: gb.from_xgboost(object(), features=["pressure_Pa", "velocity_m_per_s"]), "booster"),
        (lambda: gb.from_onnx(12, features=["pressure_Pa", "velocity_m_per_s"]), "model"),
    ]


def test_every_bad_argument_is_a_greybox_error_naming_it(tmp_path, model):
    wrong = []
    for call, name in _bad_calls(tmp_path, model):
        try:
            call()
            wrong.append((name, "no error"))
        except gb.GreyboxError as e:
            assert isinstance(e, ValueError)
            if not str(e).startswith(f"{name}:"):
                wrong.append((name, str(e)))
        except Exception as e:
            wrong.append((name, repr(e)))
    assert wrong == []


@pytest.mark.parametrize(
    "name",
    [n for n in gb.__all__ if callable(getattr(gb, n)) and not isinstance(getattr(gb, n), type)],
)
def test_every_public_function_converts_argument_errors(name):
    """Each public function is wrapped (a future one cannot forget it)."""
    assert hasattr(getattr(gb, name), "__wrapped__"), name


def test_models_and_laws_pickle_bit_for_bit(model, tmp_path):
    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(100, 2100, 500), rng.uniform(10, 260, 500)])
    p, v = rng.uniform(2e8, 3e9, 500), rng.uniform(0.2, 4.5, 500)
    for m in model:
        back = pickle.loads(pickle.dumps(m))
        assert isinstance(back, gb.Model) and back.content_hash == m.content_hash
        for a, b in zip(m.predict(X), back.predict(X)):
            assert np.array_equal(a, b)
        law = m.law()
        assert np.array_equal(pickle.loads(pickle.dumps(law)).mu(p, v).mu, law.mu(p, v).mu)
    m.save(tmp_path / "m.json")
    law = gb.load_law(tmp_path / "m.json")
    assert np.array_equal(pickle.loads(pickle.dumps(law)).mu(p, v).mu, law.mu(p, v).mu)


def test_a_law_refuses_states_no_contact_has(model, tmp_path):
    """Negative pressure, 0 K or a NaN speed: an error naming the array and the index, on the
    law and on the model (the C ABI's own check, greybox_core::contact::check_states)."""
    m = model[0]
    m.save(tmp_path / "m.json")
    law = gb.load_law(tmp_path / "m.json")
    for call, text in [
        (lambda: law.mu([1e9, -1e9], [1.0, 1.0]), "pressure[1] = -1000000000 Pa"),
        (lambda: law.mu([1e9], [1.0], temperature_K=[0.0]), "temperature[0] = 0 K"),
        (lambda: law.mu([1e9], [float("nan")]), "velocity[0]"),
        (lambda: m.mu([-1.0], [1.0]), "pressure[0] = -1 Pa"),
    ]:
        with pytest.raises(gb.GreyboxError, match=text.replace("[", r"\[").replace("]", r"\]")):
            call()


def test_an_export_grid_outside_the_models_domain_is_said(model, tmp_path):
    """The Pa/MPa slip SI arguments invite: a grid of MPa numbers given as Pa is possible
    physics, but lies entirely outside the model's domain: a warning naming the factor, and
    the report's `domain` field counts the points; a grid inside says nothing."""
    m = model[0]
    d = m.law().domain
    assert d is not None
    p = [d["pressure_pa"]["min"], d["pressure_pa"]["max"]]
    v = [d["sliding_velocity_m_s"]["min"], d["sliding_velocity_m_s"]["max"]]
    with pytest.warns(gb.UnusualValueWarning, match="multiplied by 1000000"):
        r = gb.export_table(m, "csv", tmp_path / "slip.csv", pressure_Pa=[x / 1e6 for x in p], velocity_m_per_s=v)
    assert r["domain"]["points_outside"] == r["domain"]["grid_points"] > 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = gb.export_table(m, "csv", tmp_path / "in.csv", pressure_Pa=p, velocity_m_per_s=v)
    assert r["domain"]["points_outside"] == 0


SNIPPET = """
import numpy as np
import numpy.typing as npt
import greybox as gb

p: npt.NDArray[np.float64] = np.linspace(1e9, 2e9, 5)
v = np.full(5, 1.5)
m = gb.load_model("svr.json")
pred: gb.Prediction = m.mu(p, v, temperature_K=np.full(5, 300.0))
vals: gb.LawValues = m.law().mu(pressure_Pa=p, velocity_m_per_s=[1.0, 2.0, 3.0, 4.0, 5.0])
rows = m.predict(np.zeros((3, 2)))
t = gb.hertz(np.array([100.0, 200.0]), radius_mm=17.0, e1_GPa=650.0, nu1=0.22)
r = gb.export_table(m, "csv", "o.csv", pressure_Pa=p, velocity_m_per_s=v)
ds = gb.identify(["recordings"], "d.csv", track_radii_mm=np.array([20.0]))
"""


def mypy(tmp_path, code):
    f = tmp_path / "snippet.py"
    f.write_text(code)
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", str(tmp_path / "cache"), str(f)],
        capture_output=True,
        text=True,
    )


def test_numpy_arrays_type_check_with_mypy(tmp_path):
    if os.environ.get("GREYBOX_REQUIRE_REFERENCES") != "1":
        pytest.importorskip("mypy")
    r = mypy(tmp_path, SNIPPET)
    assert r.returncode == 0, r.stdout + r.stderr
    # and the hints are read (a wrong argument type is caught, not passed as Any)
    r = mypy(tmp_path, SNIPPET + "m.mu(p, v, margin='wide')\n")
    assert r.returncode == 1 and 'Argument "margin"' in r.stdout, r.stdout + r.stderr


def test_fits_docstring_states_the_librarys_numeric_defaults():
    """The numbers `fit`'s docstring gives for its `None` defaults are the library's."""
    d = gb.settings_defaults("fit")
    for key in ("folds", "inner_folds", "seed", "bootstrap", "importance_repeats"):
        assert f"{key} {d[key]}" in gb.fit.__doc__, (key, d[key])


def test_a_model_imported_in_python_records_its_provenance(tmp_path):
    """As `greybox import` does: the model file names the call that made it and greybox's
    version, and the file it read (hashed)."""
    rng = np.random.default_rng(5)
    X = np.column_stack([rng.uniform(2e8, 2e9, 40), rng.uniform(0.5, 4.0, 40)])
    y = 0.4 - 0.05 * X[:, 1]
    feats = ["pressure_Pa", "velocity_m_per_s"]
    est = RandomForestRegressor(n_estimators=3, random_state=0).fit(X, y)
    m = gb.from_sklearn(est, features=feats, X_train=X)
    prov = json.loads(m.to_json())["provenance"]
    assert prov["command"][0] == "greybox.from_sklearn", prov
    assert prov["version"] == gb.__version__, prov
    path = tmp_path / "rf.sklearn.json"
    path.write_text(gb.export_sklearn_json(est))
    imported = gb.import_model(path, features=feats, X_train=X)
    prov = json.loads(imported.to_json())["provenance"]
    assert prov["command"][0] == "greybox.import_model"
    assert [i["role"] for i in prov["inputs"]] == ["model"], prov


def test_a_model_object_is_named_as_such_in_provenance(model, tmp_path):
    """A Model passed where a model or law file goes is written to a temporary file for the
    call; the provenance names it as the Python object it was, with its content hash."""
    m = model[0]
    d = m.law().domain
    assert d is not None
    p = [d["pressure_pa"]["min"], d["pressure_pa"]["max"]]
    v = [d["sliding_velocity_m_s"]["min"], d["sliding_velocity_m_s"]["max"]]
    gb.export_table(m, "csv", tmp_path / "t.csv", pressure_Pa=p, velocity_m_per_s=v)
    prov = json.loads((tmp_path / "t.csv.provenance.json").read_text())
    law = [i for i in prov["inputs"] if i["role"] == "law"]
    assert len(law) == 1 and f"python-object-greybox.Model-{m.family}-{m.content_hash[:12]}" in law[0]["path"], prov
