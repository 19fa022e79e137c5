"""The package behaves as Python users expect (issue 45, item 4): silent unless asked for
progress, Ctrl-C scoped to the interrupted call, Law and Model objects wherever a file is,
NumPy broadcasting, one exception hierarchy, provenance of the Python call, laws that pickle
their content, integer columns kept integer, and the CLI found without an environment
variable. Real calls throughout, no mocks."""

import _thread
import json
import logging
import os
import pickle
import subprocess
import threading

import numpy as np
import pytest
from conftest import GREYBOX_CLI, REPO, find_cli

import greybox as gb

LAW = '{"law": "usui-childs", "mu": 0.5, "m": 0.8, "n": 1.0, "k_MPa": 500}'


def small_cut(tmp_path, length_m="2.0e-5"):
    """The example set-up made small (coarse particles, a short cut): a second or so."""
    setup = os.path.join(REPO, "examples", "aisi1045-cut.toml")
    text = open(setup).read().replace("spacing_m = 1.0e-5", "spacing_m = 2.5e-5").replace("cut_length_m = 1.0e-3", f"cut_length_m = {length_m}")
    p = tmp_path / f"cut-{length_m}.toml"
    p.write_text(text)
    return p


@pytest.fixture
def law_file(tmp_path):
    (tmp_path / "law.json").write_text(LAW)
    return tmp_path / "law.json"


@pytest.fixture(scope="module")
def sk_model():
    """A small scikit-learn forest on (contact pressure MPa, velocity m/s) as a greybox model."""
    from sklearn.ensemble import RandomForestRegressor

    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(500, 2500, 200), rng.uniform(0.5, 4.0, 200)])
    y = 0.6 - 0.0001 * X[:, 0] - 0.05 * X[:, 1]
    est = RandomForestRegressor(n_estimators=5, max_depth=4, random_state=0).fit(X, y)
    return gb.from_sklearn(est, features=["contact_pressure_MPa", "sliding_velocity_m_per_s"], X_train=X)


# 1. progress


def test_silent_by_default_and_a_callback_sees_monotonic_progress_on_the_calling_thread(tmp_path, capfd):
    setup = small_cut(tmp_path)
    gb.simulate_cut(setup, tmp_path / "quiet", as_frame=False)
    assert capfd.readouterr() == ("", "")

    seen = []
    gb.simulate_cut(setup, tmp_path / "watched", as_frame=False, progress=lambda stage, done, total: seen.append((stage, done, total, threading.get_ident())))
    assert seen, "no progress reported"
    assert {s[3] for s in seen} == {threading.get_ident()}  # on the calling thread
    for stage in {s[0] for s in seen}:
        done = [s[1] for s in seen if s[0] == stage]
        assert done == sorted(done), (stage, done)
        total = seen[-1][2]
        assert total is None or done[-1] <= total
    assert seen[-1][1] > 0


def test_progress_true_logs_to_the_greybox_logger(tmp_path, caplog):
    with caplog.at_level(logging.INFO, logger="greybox"):
        gb.simulate_cut(small_cut(tmp_path), tmp_path / "logged", as_frame=False, progress=True)
    assert any(r.name == "greybox" and r.message.startswith("simulate_cut: ") for r in caplog.records)


def test_progress_is_a_keyword_of_the_long_calls_only():
    import inspect

    for name in ["simulate_cut", "simulate_pin", "ploughing_correction", "fit", "identify", "couple", "report"]:
        assert inspect.signature(getattr(gb, name)).parameters["progress"].default is None, name
    with pytest.raises(gb.InputError, match="progress"):
        gb.simulate_cut("c.toml", "out", progress="yes")


# 2. interrupts scoped to the call


def test_ctrl_c_in_the_main_thread_leaves_another_threads_call_running(tmp_path):
    """A cut runs in a thread; the main thread's long cut gets Ctrl-C once the other is
    under way: the main call raises KeyboardInterrupt, the other completes."""
    running = threading.Event()
    result = {}

    def other():
        try:
            result["cut"] = gb.simulate_cut(small_cut(tmp_path, "1.0e-4"), tmp_path / "other", as_frame=False, progress=lambda s, d, t: d > 0 and running.set())
        except BaseException as e:  # noqa: B036 - what the other thread saw is the point
            result["error"] = e
        finally:
            running.set()

    t = threading.Thread(target=other)
    t.start()
    interrupter = threading.Thread(target=lambda: running.wait(60) and _thread.interrupt_main())
    interrupter.start()
    with pytest.raises(KeyboardInterrupt):
        gb.simulate_cut(os.path.join(REPO, "examples", "aisi1045-cut.toml"), tmp_path / "main")  # minutes of work
    t.join()
    interrupter.join()
    assert "error" not in result, result
    assert result["cut"]["steps"] > 0
    assert not (tmp_path / "main").exists()


def test_an_exception_from_the_callback_cancels_that_call_only(tmp_path):
    class Stop(Exception):
        pass

    def stop(stage, done, total):
        if done > 0:
            raise Stop

    result = {}
    t = threading.Thread(target=lambda: result.update(cut=gb.simulate_cut(small_cut(tmp_path, "1.0e-4"), tmp_path / "kept", as_frame=False)))
    t.start()
    with pytest.raises(Stop):
        gb.simulate_cut(os.path.join(REPO, "examples", "aisi1045-cut.toml"), tmp_path / "cancelled", progress=stop)
    t.join()
    assert result["cut"]["steps"] > 0
    assert not (tmp_path / "cancelled").exists()


# 3. Law and Model objects wherever a file is


def test_law_and_model_objects_go_where_files_do(tmp_path, law_file, sk_model):
    grid = {"pressure_Pa": [5e8, 1e9, 2e9], "velocity_m_per_s": [0.5, 1.0, 2.0]}
    gb.export_table(law_file, "csv", tmp_path / "from_path.csv", **grid)
    gb.export_table(gb.load_law(law_file), "csv", tmp_path / "from_law.csv", **grid)
    assert (tmp_path / "from_law.csv").read_text() == (tmp_path / "from_path.csv").read_text()

    gb.export_table(sk_model, "csv", tmp_path / "from_model.csv", **grid)
    gb.export_table(sk_model.law(), "csv", tmp_path / "from_model_law.csv", **grid)
    assert (tmp_path / "from_model.csv").read_text() == (tmp_path / "from_model_law.csv").read_text()

    grey = gb.grey_box_law(sk_model, tmp_path / "grey.json")  # the model is saved beside the law
    p, v = np.array([1.0e9, 1.5e9]), np.array([1.0, 2.0])
    np.testing.assert_allclose(grey.mu(p, v).mu, sk_model.mu(p, v).value, rtol=1e-12)

    cut = gb.simulate_cut(small_cut(tmp_path), tmp_path / "cut", law=gb.load_law(law_file), as_frame=False)
    assert cut["steps"] > 0


# 4. broadcasting


def test_mu_broadcasts_like_numpy(law_file, sk_model):
    law = gb.load_law(law_file)
    v = np.array([0.5, 1.0, 2.0])
    assert law.mu(1e9, v).mu.shape == (3,)
    np.testing.assert_array_equal(law.mu(1e9, v).mu, law.mu(np.full(3, 1e9), v).mu)
    grid = law.mu(np.array([[5e8], [1e9]]), v)
    assert grid.mu.shape == grid.in_domain.shape == (2, 3)
    np.testing.assert_array_equal(grid.mu[1], law.mu(1e9, v).mu)
    assert law.mu(1e9, 1.0).mu.shape == ()
    pred = sk_model.mu(np.array([[1e9], [2e9]]), v)
    assert pred.value.shape == pred.low.shape == pred.in_domain.shape == (2, 3)
    with pytest.raises(gb.InputError, match="do not broadcast"):
        law.mu([1e9, 2e9], v)


# 5. one exception hierarchy


def test_errors_are_one_hierarchy(tmp_path, law_file):
    with pytest.raises(gb.MissingFileError) as e:
        gb.load_law(tmp_path / "absent.json")
    assert isinstance(e.value, FileNotFoundError) and isinstance(e.value, gb.GreyboxError)
    with pytest.raises(FileNotFoundError):
        gb.simulate_cut(tmp_path / "absent.toml", tmp_path / "out")
    with pytest.raises(gb.MissingFileError):
        gb.read_dataset(tmp_path / "absent.csv")
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(gb.InputError) as e:
        gb.load_law(tmp_path / "bad.json")
    assert isinstance(e.value, ValueError) and "bad.json" in str(e.value)
    with pytest.raises(gb.SettingsError):
        gb.export_table(law_file, "csv", tmp_path / "t.csv", units="furlongs")
    # wrong calls are InputErrors too, never a bare TypeError
    with pytest.raises(gb.InputError, match="unexpected keyword"):
        gb.simulate_cut("c.toml", "out", nonsense=1)
    with pytest.raises(gb.InputError):
        gb.load_law()
    with pytest.raises(gb.InputError, match="deform_objects"):
        gb.export_table(law_file, "deform", tmp_path / "t.key", deform_objects=["tool"])
    assert issubclass(gb.SettingsError, gb.InputError) and issubclass(gb.InputError, ValueError)


# 6. provenance of the Python call


def test_provenance_records_the_function_and_its_options(tmp_path):
    gb.simulate_cut(small_cut(tmp_path), tmp_path / "cut", force=True, as_frame=False)
    with open(tmp_path / "cut" / "provenance.json") as f:
        command = json.load(f)["command"]
    assert command[0] == "greybox.simulate_cut"
    options = json.loads(command[1])
    assert options["force"] is True and options["fraction"] == 1.0 and options["out"] == str(tmp_path / "cut") and options["law"] is None


# 7. a pickled law carries its content


def test_a_pickled_law_carries_its_content(tmp_path, law_file, sk_model):
    law = gb.load_law(law_file)
    p, v = np.array([5e8, 1e9]), np.array([1.0, 2.0])
    want = law.mu(p, v).mu
    data = pickle.dumps(law)
    law_file.write_text(LAW.replace('"mu": 0.5', '"mu": 0.9'))  # the file changes afterwards
    np.testing.assert_array_equal(pickle.loads(data).mu(p, v).mu, want)

    grey = gb.grey_box_law(sk_model, tmp_path / "grey.json")  # names its model file
    data = pickle.dumps(grey)
    os.remove(tmp_path / "grey.model.json")
    np.testing.assert_array_equal(pickle.loads(data).mu(p * 2, v).mu, grey.mu(p * 2, v).mu)


# 8. integer columns


def test_count_and_index_columns_stay_integer(tmp_path):
    (tmp_path / "d.csv").write_text("pin,step,n_samples,normal_force_N,cof_apparent\n1,2,300,150,0.5\n2,1,280,300,0.45\n")
    d = gb.read_dataset(tmp_path / "d.csv", as_frame=False)
    assert d["pin"].dtype == d["step"].dtype == d["n_samples"].dtype == np.int64
    assert d["normal_force_N"].dtype == np.float64  # whole values, still a float column
    cut = gb.simulate_cut(small_cut(tmp_path), tmp_path / "cut", as_frame=False)
    for name, col in cut["forces"].items():
        assert col.dtype == (np.int64 if name == "step" else np.float64), name
    # the friction windows of the contact profile are numbered
    assert cut["contact_profile"]["window"].dtype == np.int64


# 9. the CLI for the differential tests


def test_the_cli_is_the_checkouts_build_else_the_one_on_path(tmp_path, monkeypatch):
    """Without any environment variable: the build this package was made from, where there
    is one (a stale `greybox` on PATH is not compared against), else PATH's."""
    fake = tmp_path / "greybox"
    fake.write_text("#!/bin/sh\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ.get('PATH', '')}")
    built = os.path.join(REPO, "target", "release", "greybox")
    assert find_cli() == (built if os.access(built, os.X_OK) else str(fake))


# 10. the run-output settings of the command line, from Python


def test_a_cut_takes_the_command_lines_output_settings(tmp_path):
    """VTK every N steps, checkpoints and resume are the cut's settings in Python as on the
    command line (one run-output settings type): the same VTK files as `--vtk-every`, no
    partial directory left by a completed run with checkpoints, a missing checkpoint named."""
    if GREYBOX_CLI is None:
        pytest.skip("no greybox binary to compare with")
    setup = small_cut(tmp_path)
    gb.simulate_cut(setup, tmp_path / "py", vtk_every=40, checkpoint_every=50, as_frame=False)
    subprocess.run([GREYBOX_CLI, "-q", "simulate", "cutting", "--config", str(setup), "--out",
                    str(tmp_path / "cli"), "--vtk-every", "40"], check=True)
    py_vtk = sorted(os.listdir(tmp_path / "py" / "vtk"))
    assert len(py_vtk) > 2 and py_vtk == sorted(os.listdir(tmp_path / "cli" / "vtk"))
    assert not os.path.exists(tmp_path / "py.partial")
    with pytest.raises(gb.GreyboxError, match="checkpoint"):
        gb.simulate_cut(setup, tmp_path / "again", resume=tmp_path / "none.partial" / "checkpoint.json")


def test_the_report_takes_its_caps(tmp_path):
    """The report's caps are keyword arguments (the command line's flags) that reach the
    search."""
    (tmp_path / "study").mkdir()
    (tmp_path / "study" / "a").mkdir()
    (tmp_path / "study" / "a" / "dataset.csv").write_text("pin,step,normal_force_N,cof_apparent\n1,1,10,0.3\n")
    r = gb.report(tmp_path / "study")
    assert r["bytes"] > 0
    # the dataset lies one level down: with max_depth 0 the search never reaches it
    with pytest.raises(gb.GreyboxError, match="no greybox outputs found"):
        gb.report(tmp_path / "study", out=tmp_path / "shallow.html", max_depth=0)
    assert gb.settings_defaults("report")["max_entries"] == 100_000
