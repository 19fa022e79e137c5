"""One task through Python and through the command line gives the same bytes: the options and
their defaults are the library's, both surfaces only override fields. (The library side of
the same comparison is crates/greybox-cli/tests/surfaces_agree.rs.)"""

import json
import os
import subprocess

import pytest
from conftest import GREYBOX_CLI as CLI
from conftest import REPO

import greybox as gb

FORMATS = ["abaqus", "deform", "lsdyna", "csv", "table"]
LAW = '{"law": "usui-childs", "mu": 0.5, "m": 0.8, "n": 1.0, "k_MPa": 500}'

# (conftest finds the binary; under GREYBOX_REQUIRE_REFERENCES=1 its absence fails there)
pytestmark = pytest.mark.skipif(CLI is None, reason="the greybox binary is not built nor on PATH")


def cli(*args, cwd):
    r = subprocess.run([CLI, "-q", *map(str, args)], cwd=cwd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.fixture
def law(tmp_path):
    (tmp_path / "law.json").write_text(LAW)
    return tmp_path / "law.json"


@pytest.mark.parametrize("format", FORMATS)
def test_default_export_is_the_same_file_from_python_and_the_cli(law, tmp_path, format):
    cli("export", "--law", law, "--format", format, "--out", "cli.out", cwd=tmp_path)
    report = gb.export_table(law, format, tmp_path / "py.out")
    assert (tmp_path / "cli.out").read_bytes() == (tmp_path / "py.out").read_bytes()
    assert report["bytes"] == len((tmp_path / "py.out").read_bytes())


def test_the_defaults_are_the_documented_ones_and_python_can_change_each():
    d = gb.export_defaults("deform")
    assert d["deform_objects"] == [2, 1]
    assert d["deform_reference_velocity_m_per_s"] == 2.5  # 150 m/min
    assert gb.export_defaults("lsdyna")["lsdyna_table_id"] == 1000
    assert gb.export_defaults("abaqus")["units"] == "MPa-mm-s"
    assert len(d["pressure_Pa"]) == 21 and len(d["velocity_m_per_s"]) == 30


def test_overrides_from_python_match_the_cli_flags(law, tmp_path):
    cli(
        "export", "--law", law, "--format", "deform", "--out", "cli.key",
        "--deform-objects", "1,2", "--deform-reference-velocity-m-per-min", "60",
        "--pressure-MPa", "200:1000:5", "--velocity-m-per-min", "30,60,120",
        cwd=tmp_path,
    )
    gb.export_table(
        law, "deform", tmp_path / "py.key",
        pressure_Pa=[200e6, 400e6, 600e6, 800e6, 1000e6], velocity_m_per_s=[0.5, 1.0, 2.0],
        deform_objects=(1, 2), deform_reference_velocity_m_per_s=1.0,
    )
    assert (tmp_path / "cli.key").read_bytes() == (tmp_path / "py.key").read_bytes()
    cli("export", "--law", law, "--format", "lsdyna", "--out", "cli.k", "--units", "Pa-m-s",
        "--lsdyna-table-id", "5", cwd=tmp_path)
    gb.export_table(law, "lsdyna", tmp_path / "py.k", units="Pa-m-s", lsdyna_table_id=5)
    assert (tmp_path / "cli.k").read_bytes() == (tmp_path / "py.k").read_bytes()


def test_an_option_of_another_engine_or_a_mixed_unit_set_is_refused(law, tmp_path):
    with pytest.raises(gb.GreyboxError, match=r"^lsdyna_table_id: not an option of the abaqus export"):
        gb.export_table(law, "abaqus", tmp_path / "a.inp", lsdyna_table_id=3)
    with pytest.raises(gb.GreyboxError, match="MPa-mm-s"):
        gb.export_table(law, "abaqus", tmp_path / "a.inp", units="MPa-m-s")
    with pytest.raises(gb.GreyboxError, match=r"max_table_size: the table would have"):
        gb.export_table(law, "csv", tmp_path / "a.csv", max_table_size=10)
    assert not any(tmp_path.glob("a.*"))


def test_identify_and_simulate_summaries_agree(tmp_path, real_rigs):
    """identify (a real rig export) and a short cut: the same dataset bytes and summary
    numbers from Python and the command line, given the same study."""
    rigs = real_rigs
    study = os.path.join(REPO, "examples", "demo-study.toml")
    rec = os.path.join(rigs, "phoenix-te", "PPS_60N_1.tsv")
    _, py = gb.identify([rec], tmp_path / "py.csv", study=study, no_plan=True, steady="last:50%",
                        rig="phoenix-te", map=["radius=Radius:mm"], as_frame=False)
    out = cli("identify", "--study", study, "--no-plan", "--steady", "last:50%", "--rig", "phoenix-te",
              "--map", "radius=Radius:mm", "--recordings", rec, "--out", "cli.csv", "--json",
              cwd=tmp_path)
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    c = json.loads(out)
    for summary in (c, py):
        summary.pop("dataset")  # the output paths differ
    assert c == py


def test_a_cut_from_python_and_the_cli_gives_the_same_summary_and_forces(tmp_path):
    """A short coarse cut of the bundled AISI 1045 set-up: the same summary numbers and the
    same force history bytes through gb.simulate_cut and `greybox simulate cutting`."""
    src = gb.example("aisi1045-cut.toml")
    src = src.replace("spacing_m = 1.0e-5", "spacing_m = 2.5e-5").replace("cut_length_m = 1.0e-3", "cut_length_m = 1.0e-4")
    (tmp_path / "cut.toml").write_text(src)
    py = gb.simulate_cut(tmp_path / "cut.toml", tmp_path / "py", as_frame=False)
    out = cli("simulate", "cutting", "--config", "cut.toml", "--out", "cli", "--json", cwd=tmp_path)
    c = json.loads(out)
    timing = {"wall_s", "particle_steps_per_s", "particle_steps_per_s_per_core", "threads", "files", "out"}
    for key, value in c.items():
        if key not in timing and not isinstance(value, dict):
            assert py[key] == value, key
    assert (tmp_path / "cli" / "forces.csv").read_bytes() == (tmp_path / "py" / "forces.csv").read_bytes()


def test_a_refined_coarsened_cut_from_python_and_the_cli_says_the_same_merges(tmp_path):
    """A short refined cut with local time stepping and both coarsening regions: the same
    `coarsened` record (particles merged away, the energy the merges averaged out) and the
    same force history bytes through gb.simulate_cut and `greybox simulate cutting`."""
    src = gb.example("aisi1045-cut.toml")
    src = src.replace("spacing_m = 1.0e-5", "spacing_m = 2.5e-5").replace("cut_length_m = 1.0e-3", "cut_length_m = 1.5e-4")
    src = src.replace("[numerics]", "[numerics]\nlocal_time_stepping = true", 1)
    src += (
        "\n[refinement]\n"
        "regions = [{ ahead_m = 0.1e-3, behind_m = 0.01e-3, below_m = 0.03e-3, above_m = 0.3e-3 }]\n"
        "coarsen_behind_m = 0.03e-3\n"
        "coarsen_chip_above_m = 0.3e-3\n"
    )
    (tmp_path / "cut.toml").write_text(src)
    py = gb.simulate_cut(tmp_path / "cut.toml", tmp_path / "py", as_frame=False)
    c = json.loads(cli("simulate", "cutting", "--config", "cut.toml", "--out", "cli", "--json", cwd=tmp_path))
    assert c["coarsened"]["particles"] > 0, c["coarsened"]
    assert py["coarsened"] == c["coarsened"]
    assert (tmp_path / "cli" / "forces.csv").read_bytes() == (tmp_path / "py" / "forces.csv").read_bytes()


def test_every_identify_flag_is_a_python_setting_with_the_same_effect(tmp_path, real_rigs):
    """The CLI's identify flags and Python's keyword settings are one library type: the same
    real export read with the rig, a channel map, a load unit and the convention given both
    ways writes the same dataset bytes."""
    rec = os.path.join(real_rigs, "phoenix-te", "PPS_60N_1.tsv")
    cli("identify", "--rig", "phoenix-te", "--map", "radius=Radius:mm", "--convention", "article-eq7",
        "--steady", "from:30s", "--settle-s", "0.1", "--recordings", rec, "--out", "cli.csv", cwd=tmp_path)
    gb.identify(rec, tmp_path / "py.csv", steady="from:30s", rig="phoenix-te", map=["radius=Radius:mm"],
                convention="article-eq7", settle_time_s=0.1, as_frame=False)
    assert (tmp_path / "cli.csv").read_bytes() == (tmp_path / "py.csv").read_bytes()
    with pytest.raises(gb.GreyboxError, match="segment: unknown variant `steps`, expected one of `auto`"):
        gb.identify(rec, tmp_path / "x.csv", segment="steps")


def _dataset(tmp_path):
    """A small friction dataset (two loads) in the identification's columns."""
    head = ("pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,"
            "hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,"
            "plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n")
    rows = [f"1,{k},{f},{f},100,1500,textbook-max,{mu},0.01,1000,1,2,0,true,\n"
            for k, (f, mu) in enumerate([(1000.0, 0.32), (1500.0, 0.30), (1500.0, 0.31)])]
    (tmp_path / "ds.csv").write_text(head + "".join(rows))


def test_an_adhesive_correction_is_the_same_from_python_and_the_cli(tmp_path):
    """The analytic correction with stated track widths: the same dataset bytes and the same
    correction record through gb.ploughing_correction and `greybox adhesive`."""
    _dataset(tmp_path)
    out = cli("adhesive", "--data", "ds.csv", "--pin-radius-mm", "1", "--track-width", "1000:400",
              "--track-width", "1500:500", "--out", "cli.csv", "--json", cwd=tmp_path)
    _, py = gb.ploughing_correction(tmp_path / "ds.csv", tmp_path / "py.csv", pin_radius_mm=1.0,
                                    track_width=[(1000, 400), (1500, 500)], as_frame=False)
    assert (tmp_path / "cli.csv").read_bytes() == (tmp_path / "py.csv").read_bytes()
    assert json.loads(out) == py
    # the defaults are the library's: the article's pin and Table 3 from both
    cli("adhesive", "--data", "ds.csv", "--out", "cli2.csv", cwd=tmp_path)
    gb.ploughing_correction(tmp_path / "ds.csv", tmp_path / "py2.csv")
    assert (tmp_path / "cli2.csv").read_bytes() == (tmp_path / "py2.csv").read_bytes()
    with pytest.raises(gb.GreyboxError, match=r"^method: 'inverse' is not one of"):
        gb.ploughing_correction(tmp_path / "ds.csv", tmp_path / "x.csv", method="inverse")
    with pytest.raises(gb.GreyboxError, match="sim_loads"):
        gb.ploughing_correction(tmp_path / "ds.csv", tmp_path / "x.csv", sim_loads=2.5)


def test_a_pin_slide_is_the_same_from_python_and_the_cli(tmp_path):
    """A small plane-strain pin slide: the same result numbers and force history bytes
    through gb.simulate_pin and `greybox simulate pin`."""
    flags = {"pin_radius_mm": 1.0, "depth_um": 20.0, "slide_mm": 0.1, "height_mm": 0.12,
             "mu": 0.2, "spacing_um": 20.0}
    args = [x for k, v in flags.items() for x in ("--" + k.replace("_", "-"), str(v))]
    out = cli("simulate", "pin", *args, "--out", "cli", "--json", cwd=tmp_path)
    py = gb.simulate_pin(tmp_path / "py", **flags)
    c = json.loads(out)
    timing = {"wall_s", "particle_steps_per_s", "particle_steps_per_s_per_core", "threads"}
    assert {k: v for k, v in c.items() if k not in timing} == {k: v for k, v in py.items() if k not in timing}
    assert (tmp_path / "cli" / "forces.csv").read_bytes() == (tmp_path / "py" / "forces.csv").read_bytes()
    with pytest.raises(gb.GreyboxError, match="depth_um"):
        gb.simulate_pin(tmp_path / "x", depth_um=20.0, track_width_um=400.0)


def test_couple_settings_are_checked_by_the_library_with_its_names(tmp_path):
    with pytest.raises(gb.GreyboxError, match=r"^deck: the CalculiX deck is required for engine calculix"):
        gb.couple(tmp_path / "law.json")
    with pytest.raises(gb.GreyboxError, match="units"):
        gb.couple(tmp_path / "law.json", engine="command", command="true", units="MPa-m-s")
