"""Helpers of the browser tests (a module of its own name: crates/greybox-py/tests has a
conftest.py too, so `from conftest import …` would be ambiguous when both run)."""

import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _require(what: str, ok: bool) -> None:
    if ok:
        return
    if os.environ.get("GREYBOX_REQUIRE_BROWSER") == "1":
        pytest.fail(f"{what} is missing and GREYBOX_REQUIRE_BROWSER=1")
    pytest.skip(f"{what} is not installed")


def _find(*names: str):
    for n in names:
        p = shutil.which(n)
        if p:
            return p
    return None
