"""Shared data for the Python tests: a friction-like dataset over the article's ranges
(normal force 150–2000 N, sliding velocity 20–250 m/min) and seeded random query points; the
greybox command line for the differential tests (:data:`GREYBOX_CLI`)."""

import os
import shutil

import numpy as np
import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def find_cli():
    """The greybox binary, found without any environment variable: this checkout's
    ``target/release/greybox`` (``cargo build --release -p greybox-cli``: the build the
    package was made from), else ``greybox`` on PATH; None when neither is there."""
    built = os.path.join(REPO, "target", "release", "greybox")
    if os.access(built, os.X_OK):
        return built
    return shutil.which("greybox")


#: The binary the differential tests compare against (None: they skip).
GREYBOX_CLI = find_cli()

# Under CI the reference libraries and the CLI must be there: the tests that use them run,
# never skip (GREYBOX_REQUIRE_REFERENCES=1 makes a missing one an error here).
if os.environ.get("GREYBOX_REQUIRE_REFERENCES") == "1":
    import onnx  # noqa: F401
    import onnxruntime  # noqa: F401
    import pandas  # noqa: F401
    import skl2onnx  # noqa: F401
    import sklearn  # noqa: F401
    import xgboost  # noqa: F401

    assert GREYBOX_CLI is not None, "GREYBOX_REQUIRE_REFERENCES=1 but no greybox binary: not on PATH, nor at " + os.path.join(REPO, "target", "release", "greybox")


@pytest.fixture(scope="session")
def greybox_cli():
    """The greybox binary's path; the test skips where there is none (fails under
    GREYBOX_REQUIRE_REFERENCES=1, at the check above)."""
    if GREYBOX_CLI is None:
        pytest.skip("the greybox binary is not built (cargo build --release -p greybox-cli) nor on PATH")
    return GREYBOX_CLI


@pytest.fixture(scope="session")
def real_rigs():
    """The real-rig corpus (raw public exports kept outside the project, in
    ../shared/data/real-rigs beside the checkout, or GREYBOX_REAL_RIGS_DIR): skips where it is
    absent, unless GREYBOX_REQUIRE_REAL_RIGS=1 (.ci/run), where its absence fails."""
    here = os.path.dirname(os.path.abspath(__file__))
    d = os.environ.get("GREYBOX_REAL_RIGS_DIR") or os.path.join(here, "..", "..", "..", "..", "shared", "data", "real-rigs")
    if not os.path.isdir(d):
        assert os.environ.get("GREYBOX_REQUIRE_REAL_RIGS") != "1", f"GREYBOX_REQUIRE_REAL_RIGS=1 but {d} is missing"
        pytest.skip(f"the real-rig corpus {d} is not here")
    return d


FEATURES = ["normal_force_N", "sliding_velocity_m_per_min"]
DOMAIN = [(150.0, 2000.0), (20.0, 250.0)]


def friction(X):
    """A smooth μ(F, v) with the article's trends: falling with speed, mildly with load."""
    F, v = X[:, 0], X[:, 1]
    return 0.62 - 0.00009 * F - 0.25 * np.log(v / 20.0) / np.log(12.5) + 0.03 * np.sin(F / 300.0)


@pytest.fixture(scope="session")
def data():
    rng = np.random.default_rng(7)
    n = 300
    X = np.column_stack([rng.uniform(*DOMAIN[0], n), rng.uniform(*DOMAIN[1], n)])
    y = friction(X) + rng.normal(0, 0.01, n)
    Xc = np.column_stack([rng.uniform(*DOMAIN[0], 100), rng.uniform(*DOMAIN[1], 100)])
    yc = friction(Xc) + rng.normal(0, 0.01, 100)
    return X, y, Xc, yc


@pytest.fixture(scope="session")
def queries():
    """3000 seeded points over the domain widened by 10 % (some outside on purpose)."""
    rng = np.random.default_rng(11)
    lo = np.array([d[0] for d in DOMAIN])
    hi = np.array([d[1] for d in DOMAIN])
    w = hi - lo
    return rng.uniform(lo - 0.1 * w, hi + 0.1 * w, (3000, 2))
