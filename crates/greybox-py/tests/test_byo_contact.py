"""Bring-your-own models everywhere the docs promise: a model trained on the normal force
(docs/python.md's XGBoost example) with its pin contact stated at import is a friction law,
a table and a μ; without the contact the error says how to state it; features of unknown
units are refused at import; ``outside="warn"`` warns (:class:`greybox.DomainWarning`)."""

import json
import os
import subprocess
import warnings

import numpy as np
import pytest

import greybox as gb
from conftest import DOMAIN, FEATURES

xgboost = pytest.importorskip("xgboost")

# The article's pin (17 mm carbide on AISI 1045) under its eq. 7 convention: the study's
# [contact] keys.
CONTACT = {
    "pin_tip_radius_mm": 17.0,
    "pin_youngs_modulus_gpa": 650.0,
    "pin_poisson_ratio": 0.3,
    "disk_youngs_modulus_gpa": 210.0,
    "disk_poisson_ratio": 0.3,
    "convention": "article-eq7",
}


@pytest.fixture(scope="module")
def xgb(data):
    X, y, _, _ = data
    return xgboost.XGBRegressor(n_estimators=50, max_depth=3).fit(X, y)


def pressure_pa(force_n):
    h = gb.hertz(force_n, radius_mm=17.0, e1_GPa=650.0, nu1=0.3, e2_GPa=210.0, nu2=0.3,
                 convention="article-eq7", as_frame=False)
    return np.asarray(h["convention_pressure_mpa"]) * 1e6


def test_docs_xgboost_example_with_contact_is_a_law_a_table_and_a_mu(xgb, data, tmp_path):
    X = data[0]
    boosted = gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact=CONTACT)
    assert np.array_equal(boosted.predict(X).value, xgb.predict(X).astype(np.float64))
    fp = json.loads(boosted.to_json())["force_to_pressure"]
    assert fp["pressure_convention"] == "article-eq7"
    assert fp["pressure_pa_at_1_n"] == pytest.approx(pressure_pa([1.0])[0], rel=1e-12)
    # μ at contact states: the pressure of each training load maps back to that load
    rng = np.random.default_rng(3)
    F = rng.uniform(200.0, 1900.0, 200)
    v_m_per_min = rng.uniform(30.0, 240.0, 200)
    p, v = pressure_pa(F), v_m_per_min / 60.0
    want = xgb.predict(np.column_stack([F, v_m_per_min])).astype(np.float64)
    mu = boosted.mu(pressure_Pa=p, velocity_m_per_s=v)
    np.testing.assert_allclose(mu.value, want, rtol=0, atol=0)
    assert mu.in_domain.all()
    law = boosted.law()
    np.testing.assert_array_equal(law.mu(p, v).mu, want)
    d = law.domain
    assert d["pressure_pa"]["min"] == pytest.approx(pressure_pa([X[:, 0].min()])[0], rel=1e-12)
    # the saved model is a law file for exports: a table holding the booster exactly
    boosted.save(tmp_path / "xgboost.json")
    report = gb.export_table(tmp_path / "xgboost.json", "csv", tmp_path / "table.csv",
                             pressure_Pa=[d["pressure_pa"]["min"], d["pressure_pa"]["max"]],
                             velocity_m_per_s=[d["sliding_velocity_m_s"]["min"], d["sliding_velocity_m_s"]["max"]])
    assert report["max_deviation"] == 0.0 and report["exact_steps"]
    assert gb.load_law(tmp_path / "xgboost.json").mu(p, v).mu.tolist() == want.tolist()


def test_contact_from_a_study_records_the_same_map(xgb, data, tmp_path):
    X = data[0]
    study = tmp_path / "study.toml"
    study.write_text("[contact]\n" + "".join(
        f"{k} = {json.dumps(v)}\n" for k, v in CONTACT.items()))
    by_study = gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact=study)
    by_dict = gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact=CONTACT)
    key = lambda m: json.loads(m.to_json())["force_to_pressure"]  # noqa: E731
    assert key(by_study) == key(by_dict)
    # the command line records the same map from the study, and its flags override the
    # study's keys as the keys of a Python dict state them
    from conftest import GREYBOX_CLI as cli

    if cli is None:
        pytest.skip("the greybox binary is not built (cargo build --release -p greybox-cli)")
    xgb.get_booster().save_model(tmp_path / "booster.ubj")
    lo, hi = X.min(axis=0).tolist(), X.max(axis=0).tolist()

    def cli_import(*flags):
        out = tmp_path / "cli.json"
        r = subprocess.run([cli, "import", str(tmp_path / "booster.ubj"), "--features", ",".join(FEATURES),
                            "--domain", f"{lo[0]!r}:{hi[0]!r},{lo[1]!r}:{hi[1]!r}",
                            *flags, "--out", str(out)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        m = gb.load_model(out)
        os.remove(out)
        os.remove(str(out) + ".provenance.json")
        return m

    assert key(cli_import("--contact", str(study))) == key(by_dict)
    mean = gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact={**CONTACT, "convention": "textbook-mean"})
    assert key(cli_import("--contact", str(study), "--convention", "textbook-mean")) == key(mean)
    assert key(mean) != key(by_dict)


def test_without_contact_the_law_says_how_to_state_it(xgb, data):
    boosted = gb.from_xgboost(xgb, features=FEATURES, X_train=data[0])
    boosted.predict(data[0])  # predicts on forces
    for use in (boosted.law, lambda: boosted.mu([1e9], [1.0])):
        with pytest.raises(gb.GreyboxError) as e:
            use()
        msg = str(e.value)
        assert "imported without a contact" in msg and "contact=" in msg and "`contact`" in msg, msg
        assert "schema version" not in msg, msg


def test_bad_contacts_are_refused_naming_the_key(xgb, data):
    X = data[0]
    with pytest.raises(gb.GreyboxError, match="convention"):
        gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact={"pin_tip_radius_mm": 17.0})
    with pytest.raises(gb.GreyboxError, match="pin_radius_mm"):
        gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact={**CONTACT, "pin_radius_mm": 17.0})
    with pytest.raises(gb.GreyboxError, match="pin_tip_radius_mm"):
        gb.from_xgboost(xgb, features=FEATURES, X_train=X, contact={**CONTACT, "pin_tip_radius_mm": -1.0})


@pytest.mark.parametrize("bad", ["pressure", "contact_pressure_psi"])
def test_features_of_unknown_units_are_refused_at_import(bad, xgb, data):
    with pytest.raises(gb.GreyboxError) as e:
        gb.from_xgboost(xgb, features=[bad, "sliding_velocity_m_per_min"], X_train=data[0])
    msg = str(e.value)
    assert f"'{bad}'" in msg and "_MPa" in msg and "_m_per_min" in msg and "_N" in msg, msg


def test_outside_warn_warns_with_counts_and_features(xgb, data):
    boosted = gb.from_xgboost(xgb, features=FEATURES, domain=DOMAIN, contact=CONTACT)
    X = np.array([[500.0, 100.0], [5000.0, 100.0], [600.0, 120.0]])
    with pytest.warns(gb.DomainWarning, match=r"1 of 3 points .*normal_force_N") as w:
        pred = boosted.predict(X)
    assert "sliding_velocity" not in str(w[0].message)
    assert pred.in_domain.tolist() == [True, False, True]
    with pytest.raises(gb.GreyboxError, match="outside the training domain"):
        boosted.predict(X, outside="refuse")
    p = pressure_pa([500.0, 600.0])
    with pytest.warns(gb.DomainWarning, match=r"2 of 2 points .*sliding_velocity_m_per_min"):
        boosted.mu(p, [100.0, 100.0])  # m/s: far beyond 250 m/min
    law = boosted.law()
    with pytest.warns(gb.DomainWarning, match=r"1 of 2 states .*pressure"):
        law.mu([p[0], 1e11], [1.5, 1.5])
    with pytest.raises(gb.GreyboxError, match="validity domain"):
        law.mu([p[0], 1e11], [1.5, 1.5], outside="refuse")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        boosted.predict(X[[0, 2]])
        boosted.mu(p, [1.5, 1.5])
        law.mu(p, [1.5, 1.5])
