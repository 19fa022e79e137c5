"""Python and the command line as one surface: per stage, the same task through `greybox …`
and through `gb.…`, **each with its own defaults** (nothing passed that a user would not
pass), gives the same bytes; and every setting of a stage's library type is a keyword of its
Python function, so no field is reachable from one surface only."""

import glob
import inspect
import json
import os
import subprocess

import numpy as np
import pytest

import greybox as gb
from conftest import GREYBOX_CLI as CLI

pytestmark = pytest.mark.skipif(CLI is None, reason="the greybox binary is not built nor on PATH")


def cli(*args, cwd, ok=True):
    r = subprocess.run([CLI, "-q", *map(str, args)], cwd=cwd, capture_output=True, text=True)
    if ok:
        assert r.returncode == 0, r.stderr
    return r


# The Python function of each stage and the library settings type it sends (the same JSON
# `greybox <stage>` flattens into its flags).
STAGES = {
    "identify": gb.identify,
    "synth": gb.synth,
    "hertz": gb.hertz,
    "fit": gb.fit,
    "law": gb.grey_box_law,
    "adhesive": gb.ploughing_correction,
    "pin": gb.simulate_pin,
    "couple": gb.couple,
    "windows": gb.windows,
    "flow_curves": gb.fit_flow_curves,
    "rate_sensitivity": gb.fit_rate_sensitivity,
    "validate": gb.validate,
    "cut": gb.simulate_cut,
    "predict": gb.Model.predict,
    "import": gb.import_model,
}
# Python names for settings a function takes positionally under another name.
POSITIONAL = {("hertz", "force_N"): "normal_force_N", ("cut", "config"): "setup"}


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_every_setting_of_a_stage_is_a_python_keyword(stage):
    params = inspect.signature(STAGES[stage]).parameters
    takes_plan = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values())
    plan = set(gb.settings_defaults("plan")) if takes_plan else set()
    missing = [k for k in gb.settings_defaults(stage)
               if POSITIONAL.get((stage, k), k) not in params and k not in plan]
    assert not missing, f"gb.{STAGES[stage].__name__} lacks settings {missing}"


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_a_python_default_is_the_librarys(stage):
    """A keyword that states its default in the signature states the library's (None: the
    library's, whatever it is): Python cannot drift from the command line's defaults."""
    params = inspect.signature(STAGES[stage]).parameters
    defaults = gb.settings_defaults(stage)
    drift = {}
    for key, library in defaults.items():
        p = params.get(POSITIONAL.get((stage, key), key))
        if p is None or p.default in (None, inspect.Parameter.empty):
            continue
        if p.default != library:
            drift[key] = (p.default, library)
    assert not drift, f"gb.{STAGES[stage].__name__}: Python default != library default: {drift}"


def test_rig_profiles_are_the_ones_the_cli_lists(tmp_path):
    """`gb.rig_profiles()` and `greybox identify --list-rigs` list the same profiles, in
    order, and every name is accepted as `rig=` (`auto` too); another name is refused."""
    names = [p["name"] for p in gb.rig_profiles()]
    listed = [line.split()[0] for line in cli("identify", "--list-rigs", cwd=tmp_path).stdout.splitlines()
              if line and not line[0].isspace()]
    assert names == listed and len(names) >= 5, (names, listed)
    assert all(p["mode"] in ("continuous", "stepped", "reciprocating") for p in gb.rig_profiles())
    with pytest.raises(gb.GreyboxError, match="rig"):
        gb.identify([tmp_path], tmp_path / "d.csv", rig="list")


def _rig_files(real_rigs):
    files = sorted(f for f in glob.glob(os.path.join(real_rigs, "*", "*")) if os.path.isfile(f))
    assert len(files) >= 5, files
    return files


def test_identify_with_each_sides_defaults_writes_the_same_dataset(tmp_path, real_rigs):
    """Every real export of the corpus, nothing but the recording given: both surfaces
    succeed with the same dataset bytes, or both refuse it."""
    agreed = 0
    for k, rec in enumerate(_rig_files(real_rigs)):
        r = cli("identify", "--recordings", rec, "--out", f"cli{k}.csv", cwd=tmp_path, ok=False)
        try:
            table, summary = gb.identify(rec, tmp_path / f"py{k}.csv", as_frame=False)
        except gb.GreyboxError as e:
            assert r.returncode != 0, f"{rec}: Python refused ({e}) but the CLI identified it"
            continue
        assert r.returncode == 0, f"{rec}: the CLI refused ({r.stderr}) but Python identified it"
        assert (tmp_path / f"cli{k}.csv").read_bytes() == (tmp_path / f"py{k}.csv").read_bytes(), rec
        assert summary["pressure_convention"] == "textbook-max"  # no study behind the user's back
        agreed += 1
    assert agreed >= 3


def test_a_studys_plan_is_used_when_it_has_one_on_both_surfaces(tmp_path):
    study = gb.example("demo-study.toml")
    (tmp_path / "study.toml").write_text(study)
    cli("synth", "--study", "study.toml", "--normal-force-count", "2", "--velocity-count", "2",
        "--out", "rec", cwd=tmp_path)
    cli("identify", "--study", "study.toml", "--normal-force-count", "2", "--velocity-count", "2",
        "--recordings", "rec", "--out", "cli.csv", cwd=tmp_path)
    _, summary = gb.identify(tmp_path / "rec", tmp_path / "py.csv", study=tmp_path / "study.toml",
                             normal_force_count=2, velocity_count=2)
    assert (tmp_path / "cli.csv").read_bytes() == (tmp_path / "py.csv").read_bytes()
    assert summary["pressure_convention"] == "article-eq7"  # the study's, because it was given


def test_synth_with_each_sides_defaults_writes_the_same_recordings(tmp_path):
    cli("synth", "--normal-force-count", "2", "--velocity-count", "2", "--out", "cli", cwd=tmp_path)
    gb.synth(tmp_path / "py", normal_force_count=2, velocity_count=2)
    names = sorted(os.listdir(tmp_path / "cli"))
    assert names == sorted(os.listdir(tmp_path / "py"))
    for n in names:
        if n.endswith(".csv"):
            assert (tmp_path / "cli" / n).read_bytes() == (tmp_path / "py" / n).read_bytes(), n


def test_hertz_with_each_sides_defaults_gives_the_same_contact():
    rows = json.loads(cli("hertz", "--force-N", "60", "500", "--json", cwd=".").stdout)
    table = gb.hertz([60, 500], as_frame=False)
    assert [r["max_pressure_mpa"] for r in rows] == table["max_pressure_mpa"].tolist()
    assert [r["contact_half_width_mm"] for r in rows] == table["contact_half_width_mm"].tolist()


def _fitted_model(tmp_path):
    """A small model fitted by greybox (a contact recorded from its dataset)."""
    rng = np.random.default_rng(3)
    head = ("pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,"
            "hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,"
            "plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n")
    rows = []
    for k in range(40):
        f, v = 150 + 50 * (k % 8), 20 + 40 * (k // 8)
        p = 1068.7 * (f / 60) ** (1 / 3)
        rows.append(f"{k // 8 + 1},{k},{f},{f},{v},{p:.6f},textbook-max,{0.5 - 0.001 * v + rng.normal(0, 0.005):.5f},0.01,1000,1,2,0,true,\n")
    (tmp_path / "ds.csv").write_text(head + "".join(rows))
    gb.fit("ds.csv" if os.getcwd() == str(tmp_path) else tmp_path / "ds.csv", tmp_path / "fit", families=["svr"], skip_nested=True, bootstrap=10,
           importance_repeats=2, folds=3)
    return tmp_path / "fit" / "models" / "svr.json"


def test_fit_and_the_law_with_each_sides_defaults_give_the_same_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # both surfaces given the same relative paths
    _fitted_model(tmp_path)
    cli("fit", "--data", "ds.csv", "--out", "cli-fit", "--families", "svr", "--skip-nested",
        "--bootstrap", "10", "--importance-repeats", "2", "--folds", "3", cwd=tmp_path)
    a, b = (json.loads((tmp_path / d / "report.json").read_text()) for d in ("fit", "cli-fit"))
    for report in (a, b):
        for family in report["families"]:
            family.pop("seconds")  # wall time, the one thing that may differ
    assert a == b
    X = np.array([[300.0, 40.0], [1500.0, 200.0]])
    np.testing.assert_array_equal(gb.load_model(tmp_path / "fit/models/svr.json").predict(X).value,
                                  gb.load_model(tmp_path / "cli-fit/models/svr.json").predict(X).value)
    cli("law", "--model", "fit/models/svr.json", "--out", "cli-law.json", cwd=tmp_path)
    gb.grey_box_law("fit/models/svr.json", tmp_path / "py-law.json")
    assert (tmp_path / "cli-law.json").read_bytes() == (tmp_path / "py-law.json").read_bytes()
    law = json.loads((tmp_path / "py-law.json").read_text())
    # the file states the cap and the contact, even where they are the defaults
    assert "shear_cap_k_MPa" in law and law["shear_cap_k_MPa"] is None
    assert "contact" in law["inner"]


def test_the_demos_law_exports_a_default_table_on_both_surfaces(tmp_path):
    """`greybox export --format table` of a grey-box law with a shear cap (the demo's)."""
    model = _fitted_model(tmp_path)
    gb.grey_box_law(model, tmp_path / "law.json", shear_cap_k_MPa=600)
    cli("export", "--law", "law.json", "--format", "table", "--out", "cli.table", cwd=tmp_path)
    gb.export_table(tmp_path / "law.json", "table", tmp_path / "py.table")
    assert (tmp_path / "cli.table").read_bytes() == (tmp_path / "py.table").read_bytes()


def test_import_reads_tables_by_name_and_takes_the_contact_from_training_data(tmp_path):
    sk = pytest.importorskip("sklearn.ensemble")
    pd = pytest.importorskip("pandas")
    _fitted_model(tmp_path)
    ds = gb.read_dataset(tmp_path / "ds.csv", as_frame=True)
    X = ds[["normal_force_N", "sliding_velocity_m_per_min"]]
    est = sk.RandomForestRegressor(n_estimators=5, random_state=0).fit(X, ds["cof_apparent"])
    # the same training table, columns reordered: the same domain (taken by name)
    a = gb.from_sklearn(est, X_train=X)
    b = gb.from_sklearn(est, X_train=X[X.columns[::-1]])
    assert a.training_domain == b.training_domain
    # the dataset's table gives the contact, as --training-data gives it from the CSV
    m = gb.from_sklearn(est, X_train=ds)
    assert m.law().domain is not None
    (tmp_path / "rf.json").write_text(json.dumps(gb.export_sklearn(est)))
    cli("import", "rf.json", "--training-data", "ds.csv", "--out", "cli-rf.json", cwd=tmp_path)
    via_cli = gb.load_model(tmp_path / "cli-rf.json")
    via_py = gb.import_model(tmp_path / "rf.json", training_data=tmp_path / "ds.csv")
    assert via_cli.training_domain == via_py.training_domain == m.training_domain
    assert json.loads(via_cli.to_json())["force_to_pressure"] == json.loads(m.to_json())["force_to_pressure"]
    # a feature set that can never be a friction law is refused at import, naming what is missing
    est2 = sk.RandomForestRegressor(n_estimators=2, random_state=0).fit(ds[["normal_force_N", "hertz_pressure_MPa"]], ds["cof_apparent"])
    with pytest.raises(gb.GreyboxError, match="no sliding velocity"):
        gb.from_sklearn(est2, X_train=ds)
    assert isinstance(ds, pd.DataFrame)


# One quad in a physical surface "COATING" (Gmsh 4.1).
MESH = ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"COATING\"\n$EndPhysicalNames\n"
        "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n"
        "$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n"
        "$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n")


def test_windows_with_each_sides_defaults_write_the_same_files(tmp_path):
    (tmp_path / "tool.msh").write_text(MESH)
    cli("windows", "--mesh", "tool.msh", "--out", "cli", cwd=tmp_path)
    summary = gb.windows(tmp_path / "tool.msh", tmp_path / "py")
    assert summary["windows"] and summary["elements"] == 1
    for name in ("windows.json", "windows.csv", "windows_frcwin.key", "windows.vtk"):
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name


STEEL_SETUP = os.path.join(os.path.dirname(__file__), "..", "..", "greybox-sweep", "tests", "data",
                           "synthetic-steel-setup.toml")


def _without_wall_time(path):
    """results.csv without its wall_s column (the one value that differs run to run)."""
    rows = [line.split(",") for line in open(path).read().splitlines()]
    k = rows[0].index("wall_s")
    return [r[:k] + r[k + 1:] for r in rows]


def test_validate_with_each_sides_defaults_gives_the_same_results(tmp_path, monkeypatch):
    """The suite file is the interface: `greybox bench validate` and `gb.validate`, each with
    its own default suite (validation/suite.toml) and output directory, cut the same
    conditions with the same friction models and calibrate them alike."""
    os.makedirs(tmp_path / "validation")
    with open(tmp_path / "validation" / "conditions.csv", "w") as f:
        f.write("id,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,"
                "clearance_deg,edge_radius_um,cutting_force_N_per_mm,feed_force_N_per_mm,chip_ratio\n")
        for k, (v, ff) in enumerate([(30, 70.0), (90, 60.0), (300, 50.0)]):
            f.write(f"C{k + 1},AISI 1045,synthetic,{v},0.06,15,7,20,200,{ff},2.0\n")
    with open(tmp_path / "validation" / "suite.toml", "w") as f:
        f.write(f"""data = "conditions.csv"
[[material]]
name = "AISI 1045"
setup = "{os.path.abspath(STEEL_SETUP)}"
run_speed_m_per_min = 300.0
calibration = ["C2"]
mu_bracket = [0.2, 0.8]
friction = [
  {{ kind = "coulomb-calibrated" }},
  {{ kind = "calibrated", name = "mu(v)", law = {{ law = "power", mu_ref = 0.4, p_ref_MPa = 1000.0, v_ref_m_per_min = 60.0, clamp = [0.05, 1.0] }}, grid = [{{ field = "b", values = [-0.3, 0.0] }}] }},
]
""")
    cli("bench", "validate", "--tool", "adiabatic", "--fraction", "0.5", cwd=tmp_path)
    os.rename(tmp_path / "validation-out", tmp_path / "cli-out")
    monkeypatch.chdir(tmp_path)
    v = gb.validate(tool=["adiabatic"], fraction=0.5)
    assert [s["friction"] for s in v["summaries"]] == ["coulomb-calibrated"] * 2 + ["mu(v)"] * 2
    assert _without_wall_time(tmp_path / "cli-out" / "results.csv") == \
        _without_wall_time(tmp_path / "validation-out" / "results.csv")
    # the cuts as sweep cases on a local pool of the greybox program on PATH: the same results
    monkeypatch.setenv("PATH", os.path.dirname(os.path.abspath(CLI)) + os.pathsep + os.environ["PATH"])
    gb.validate(tool=["adiabatic"], fraction=0.5, out="pool-out", executor="local", jobs=2)
    assert _without_wall_time(tmp_path / "pool-out" / "results.csv") == \
        _without_wall_time(tmp_path / "validation-out" / "results.csv")
    assert glob.glob(str(tmp_path / "pool-out" / "cuts" / "batch-01" / "cases" / "*" / "done.json"))
