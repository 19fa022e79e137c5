"""The walkthrough of docs/python.md type-checks under ``mypy --strict`` as written: a reader
who copies its blocks into a typed project gets no error from the package's own signatures
(``progress=`` of the long calls, optional results). The blocks are taken in order, as
scripts/run_doc_python.py runs them."""

import importlib.util
import os
import subprocess
import sys

import pytest

REPO = os.path.join(os.path.dirname(__file__), "..", "..", "..")


def doc_blocks():
    spec = importlib.util.spec_from_file_location("run_doc_python", os.path.join(REPO, "scripts", "run_doc_python.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    with open(os.path.join(REPO, "docs", "python.md"), encoding="utf-8") as f:
        return mod.blocks(f.read())


def test_the_python_walkthrough_passes_mypy_strict(tmp_path):
    if os.environ.get("GREYBOX_REQUIRE_REFERENCES") != "1":
        pytest.importorskip("mypy")
    blocks = doc_blocks()
    assert blocks
    code = "\n".join(f"# docs/python.md:{line}\n{text}" for line, text in blocks)
    f = tmp_path / "walkthrough.py"
    f.write_text(code)
    r = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
         "--ignore-missing-imports", str(f)],
        capture_output=True, text=True,
    )
    assert r.returncode == 0, r.stdout + r.stderr
