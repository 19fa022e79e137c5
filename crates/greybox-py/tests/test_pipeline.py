"""The article's pipeline from Python, stage by stage, each checked against an independent
reference: Johnson's Hertz formulas, the virtual rig's ground truth, the dataset on disk,
the model file's own predictions, the exported table's numbers, the simulation's files."""

import json
import math
import os
import threading
import time

import numpy as np
import pytest

import greybox as gb


def test_hertz_matches_johnson_sphere_formulas():
    F = np.array([50.0, 500.0, 2000.0])
    R, E1, n1, E2, n2 = 17.0, 650.0, 0.22, 210.0, 0.3
    t = gb.hertz(F, radius_mm=R, e1_GPa=E1, nu1=n1, e2_GPa=E2, nu2=n2, as_frame=False)
    e_star = 1.0 / ((1 - n1**2) / (E1 * 1e9) + (1 - n2**2) / (E2 * 1e9))
    a = (3 * F * (R * 1e-3) / (4 * e_star)) ** (1 / 3)  # Johnson (1985) eq. 4.22
    p0 = 3 * F / (2 * math.pi * a**2)
    np.testing.assert_allclose(t["contact_half_width_mm"], a * 1e3, rtol=1e-12)
    np.testing.assert_allclose(t["max_pressure_mpa"], p0 / 1e6, rtol=1e-12)
    np.testing.assert_allclose(t["mean_pressure_mpa"], 2 / 3 * p0 / 1e6, rtol=1e-12)
    with pytest.raises(gb.GreyboxError, match="convention: unknown variant `nope`, expected one of `textbook-max`"):
        gb.hertz(F, convention="nope")


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A 4 × 4 virtual campaign, identified against its plan, corrected for ploughing."""
    d = tmp_path_factory.mktemp("campaign")
    (d / "study.toml").write_text(gb.example("demo-study.toml"))  # stated on both stages
    s = gb.synth(d / "recordings", study=d / "study.toml", normal_force_count=4, velocity_count=4)
    ds, summary = gb.identify([d / "recordings"], d / "dataset.csv", study=d / "study.toml", normal_force_count=4, velocity_count=4, truth=d / "recordings" / "ground_truth.csv", as_frame=False)
    adh, corr = gb.ploughing_correction(d / "dataset.csv", d / "adhesive.csv", as_frame=False)
    return d, s, ds, summary, adh, corr


def test_identify_recovers_the_virtual_rigs_friction(campaign):
    d, synth_summary, ds, summary, _, _ = campaign
    assert len(ds["cof_apparent"]) == 16 == summary["plateaus"]
    assert summary["truth"]["max_abs_error"] < 0.01
    assert set(synth_summary["files"]) >= {"pin01.csv", "ground_truth.csv"} or len(synth_summary["files"]) > 0
    on_disk = gb.read_dataset(d / "dataset.csv", as_frame=False)
    np.testing.assert_array_equal(on_disk["cof_apparent"], ds["cof_apparent"])


def test_read_recording_gives_the_channels(campaign):
    d = campaign[0]
    rec, how = gb.read_recording(d / "recordings" / "pin01.csv", as_frame=False)
    n = len(rec["time_s"])
    assert n > 100 and np.all(np.diff(rec["time_s"]) > 0)
    assert len(rec["normal_force_N"]) == n == len(rec["tangential_force_N"])
    # the virtual rig's forces: μ = Ft/Fn within the campaign's range on the loaded samples
    loaded = rec["normal_force_N"] > 0.5 * rec["normal_force_N"].max()
    mu = rec["tangential_force_N"][loaded] / rec["normal_force_N"][loaded]
    assert 0.05 < np.median(mu) < 1.0
    assert how["columns"] and isinstance(how["layout"], str)
    with pytest.raises(gb.GreyboxError, match="unknown recording format"):
        gb.read_recording(d / "dataset.csv.provenance.json")


def test_identify_returns_a_dataframe_with_pandas(campaign):
    pd = pytest.importorskip("pandas")
    d = campaign[0]
    df = gb.read_dataset(d / "dataset.csv")
    assert isinstance(df, pd.DataFrame) and "hertz_pressure_MPa" in df.columns


def test_ploughing_correction_lowers_the_coefficient(campaign):
    _, _, ds, _, adh, corr = campaign
    assert np.all(adh["cof_adhesive"] < adh["cof_apparent"])
    assert np.all(adh["cof_adhesive"] > 0)
    assert isinstance(corr, dict) and corr


@pytest.fixture(scope="module")
def fitted(campaign):
    d = campaign[0]
    report = gb.fit(d / "adhesive.csv", d / "fit", families=["svr", "random-forest"], folds=4, inner_folds=3,
                    bootstrap=50, importance_repeats=3)
    return d, report


def test_fit_reports_every_family_and_writes_loadable_models(fitted):
    d, report = fitted
    fams = {f["family"] for f in report["report"]["families"]}
    assert fams == {"svr", "random-forest"}
    for f in report["report"]["families"]:
        assert f["held_out"] is not None and np.isfinite(f["held_out"]["metrics"]["r2"]["value"])
    assert all(os.path.exists(p) or os.path.exists(d / "fit" / p) for p in report["outputs"]["models"])
    with pytest.raises(gb.InputError, match="folds_typo"):
        gb.fit(d / "adhesive.csv", d / "fit2", folds_typo=3)
    # counts are bounded types on every surface: refused before any work, naming the key
    with pytest.raises(gb.GreyboxError, match=r"bootstrap: 1000000000 is above the cap of 100000"):
        gb.fit(d / "adhesive.csv", d / "fit2", bootstrap=10**9)
    assert not os.path.exists(d / "fit2")


def test_model_mu_with_intervals_and_domain_check(fitted):
    d, _ = fitted
    m = gb.load_model(d / "fit" / "models" / "svr.json")
    lo, hi = m.training_domain[0]
    F = np.array([lo, (lo + hi) / 2, 10 * hi])
    v_min = m.training_domain[1][0]
    with pytest.warns(gb.DomainWarning, match="1 of 3 points .*normal_force_N"):
        pred = m.predict(np.column_stack([F, np.full(3, v_min)]))
    assert list(pred.in_domain) == [True, True, False]
    q = m.interval["half_width"]
    np.testing.assert_allclose(pred.high - pred.value, q, rtol=1e-12)
    with pytest.raises(gb.GreyboxError, match="outside the training domain"):
        m.predict([[10 * hi, v_min]], outside="refuse")
    # μ(p, v) in SI goes through the dataset's Hertz map back to the model's normal force.
    c = m.to_json()
    import json

    c = json.loads(c)["force_to_pressure"]["pressure_pa_at_1_n"]
    p = c * np.cbrt(F[:2])
    by_state = m.mu(p, np.full(2, v_min / 60.0))
    np.testing.assert_allclose(by_state.value, pred.value[:2], rtol=1e-9)
    law = m.law()
    np.testing.assert_allclose(law.mu(p, np.full(2, v_min / 60.0)).mu, pred.value[:2], rtol=1e-9)


def test_export_tables_hold_the_models_values(fitted, tmp_path):
    d, _ = fitted
    m = gb.load_model(d / "fit" / "models" / "svr.json")
    law = m.law()
    dom = law.domain
    p = np.linspace(dom["pressure_pa"]["min"], dom["pressure_pa"]["max"], 5)
    v = np.linspace(dom["sliding_velocity_m_s"]["min"], dom["sliding_velocity_m_s"]["max"], 4)
    report = gb.export_table(m, "csv", tmp_path / "grid.csv", p, v)
    assert isinstance(report["line"], str) and report["max_deviation"] is not None
    t = gb.read_dataset(tmp_path / "grid.csv", as_frame=False)
    mu_col = [k for k in t if k.startswith("mu")][0]
    p_col = [k for k in t if k.startswith("pressure")][0]
    v_col = [k for k in t if "velocity" in k][0]
    scale_p = t[p_col][0] / p[0]
    scale_v = t[v_col][0] / v[0]
    ref = law.mu(t[p_col] / scale_p, t[v_col] / scale_v).mu
    np.testing.assert_allclose(t[mu_col], ref, rtol=1e-9, atol=1e-12)
    gb.export_table(d / "fit" / "models" / "svr.json", "abaqus", tmp_path / "friction.inp", p, v)
    assert "*FRICTION" in (tmp_path / "friction.inp").read_text().upper()
    with pytest.raises(gb.GreyboxError, match="format: 'ansys' is not one of abaqus"):
        gb.export_table(m, "ansys", tmp_path / "x", p, v)


def test_simulate_cut_returns_summary_and_arrays(tmp_path, fitted):
    setup = tmp_path / "cut.toml"
    src = open(os.path.join(os.path.dirname(__file__), "..", "..", "..", "examples", "aisi1045-cut.toml")).read()
    src = src.replace("spacing_m = 1.0e-5", "spacing_m = 2.5e-5").replace("cut_length_m = 1.0e-3", "cut_length_m = 1.0e-4")
    setup.write_text(src)
    # A bare learned model extrapolates far outside its training pressures: refused.
    model = gb.load_model(fitted[0] / "fit" / "models" / "svr.json")
    with pytest.raises(gb.GreyboxError, match="expected a finite μ ≥ 0"):
        gb.simulate_cut(setup, tmp_path / "bare", law=model)
    # The grey-box law around it is what goes into the cut.
    law_file = fitted[0] / "law.json"
    svr_path = fitted[0] / "fit" / "models" / "svr.json"
    before = svr_path.read_bytes()
    with pytest.raises(gb.GreyboxError, match="model"):
        gb.grey_box_law(svr_path, svr_path)  # the law file would replace its own model
    assert svr_path.read_bytes() == before
    law = gb.grey_box_law(svr_path, law_file)
    assert law.mu([1e10], [0.1]).mu[0] >= 0.05
    out = gb.simulate_cut(setup, tmp_path / "study" / "cut", law=law_file, as_frame=False, frames=2)
    assert out["particles"] > 0 and out["steps"] > 0
    assert sorted(os.listdir(tmp_path / "study" / "cut" / "frames")) == ["chip_001.svg", "chip_002.svg"]
    # the report page over the study directory: the cut and its provenance
    rep = gb.report(tmp_path / "study")
    assert rep["sections"] == ["Cutting", "Provenance"] and rep["warnings"] == []
    assert os.path.getsize(rep["path"]) == rep["bytes"] and rep["figures"] >= 8
    assert "grey-box" in out["law"]
    f = out["forces"]
    assert len(f["time_s"]) > 1 and np.all(np.isfinite(f["force_x_N_per_mm"]))
    # The summary's cutting force is the force history's mean over the averaged stretch.
    travel_mm = f["time_s"] * 2.5e3
    tail = travel_mm >= out["averaged_from_mm"] - 1e-9
    assert abs(abs(np.mean(f["force_x_N_per_mm"][tail])) - abs(out["cutting_force_n_per_mm"])) <= 0.05 * abs(out["cutting_force_n_per_mm"])
    prof = out["contact_profile"]
    assert len(prof) > 1 and all(len(v) == len(next(iter(prof.values()))) for v in prof.values())


def test_long_calls_release_the_gil(campaign, tmp_path):
    """A Python thread keeps running while greybox fits."""
    d = campaign[0]
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    # all four families: long enough (≈ 0.3 s) to count ticks in, now that a fit is fast
    gb.fit(
        d / "adhesive.csv",
        tmp_path / "fit",
        families=["mlp", "svr", "random-forest", "gradient-boosting"], folds=4, inner_folds=3,
    )
    elapsed = time.perf_counter() - start
    done.set()
    t.join()
    during = [x for x in ticks if start <= x <= start + elapsed]
    assert elapsed > 0.05 and len(during) > 0.2 * elapsed / 0.0011, (elapsed, len(during))


def test_errors_carry_the_command_lines_message(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"schema": "greybox-model", "schema_version": 99}')
    with pytest.raises(gb.GreyboxError, match=r"bad.json.*schema_version.*not supported"):
        gb.load_model(bad)
    with pytest.raises(ValueError) as e:  # GreyboxError is a ValueError
        gb.load_law(tmp_path / "missing.json")
    assert "missing.json" in str(e.value) and str(e.value).count("No such file") == 1, str(e.value)


def test_identify_a_real_rig_export_with_channel_settings(tmp_path, real_rigs, greybox_cli):
    """A real Phoenix TE67 export (the real-rig corpus) through the Python API: the rig's
    profile detected, the steady rule and the channel settings passed as in the CLI, the same
    μ as the CLI's real-rig test and the independent reference (0.1196 over the last half)."""
    rigs = real_rigs
    table, summary = gb.identify(
        [os.path.join(rigs, "phoenix-te", "PPS_60N_1.tsv")],
        tmp_path / "d.csv",
        steady="last:50%",
        rig="phoenix-te",
        map=["radius=Radius:mm"],
        as_frame=False,
    )
    assert abs(float(table["cof_apparent"][0]) - 0.119572) < 0.005
    # the same task through the CLI, with the same settings and nothing else, writes the same
    # dataset bytes (one default on both surfaces: no study, textbook-max)
    import subprocess

    cli = greybox_cli
    subprocess.run(
        [cli, "identify", "-q", "--steady", "last:50%", "--rig", "phoenix-te", "--map", "radius=Radius:mm",
         "--recordings", os.path.join(rigs, "phoenix-te", "PPS_60N_1.tsv"), "--out", str(tmp_path / "c.csv")],
        check=True,
    )
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "d.csv").read_bytes()
    channels, how = gb.read_recording(os.path.join(rigs, "pcs-mtm", "demo_7.txt"))
    assert "cof" in channels and "pcs-mtm" in json.dumps(how)


def test_fit_from_python_and_the_cli_gives_the_same_report_and_models(fitted, tmp_path, greybox_cli):
    """The same [fit] settings through gb.fit and `greybox fit`: the same report (every
    score, interval and importance) and model files that predict identically."""
    import subprocess

    d, py = fitted
    cli = greybox_cli
    r = subprocess.run(
        [cli, "-q", "fit", "--data", str(d / "adhesive.csv"), "--out", str(tmp_path / "fit"),
         "--families", "svr,random-forest", "--folds", "4", "--inner-folds", "3",
         "--bootstrap", "50", "--importance-repeats", "3"],
        capture_output=True, text=True,
    )
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "fit" / "report.json") as f:
        cli_report = json.load(f)
    with open(d / "fit" / "report.json") as f:
        py_report = json.load(f)
    for report in (cli_report, py_report):
        for family in report["families"]:
            family.pop("seconds")  # wall time, the one thing that may differ
    assert cli_report == py_report
    X = np.array([[300.0, 40.0], [1500.0, 200.0]])
    for family in ("svr", "random-forest"):
        a = gb.load_model(tmp_path / "fit" / "models" / f"{family}.json").predict(X)
        b = gb.load_model(d / "fit" / "models" / f"{family}.json").predict(X)
        np.testing.assert_array_equal(a.value, b.value)
