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

# Fixtures, imported by name into each test module (no conftest.py here: pytest runs these
# tests together with crates/greybox-py/tests, whose conftest module would be shadowed).


@pytest.fixture(scope="module")
def greybox_exe() -> Path:
    exe = Path(os.environ.get("GREYBOX_BIN", ROOT / "target" / "release" / "greybox"))
    _require(f"the greybox binary ({exe}; cargo build --release -p greybox-cli)", exe.is_file())
    return exe


@pytest.fixture(scope="module")
def browser():
    chromium = _find("chromium", "chromium-browser", "google-chrome")
    driver_path = _find("chromedriver")
    _require("chromium", chromium is not None)
    _require("chromedriver", driver_path is not None)
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        _require("selenium", False)
    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,1000"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(driver_path), options=opts)
    yield driver
    driver.quit()
