"""Shared by the browser tests: the greybox binary, a headless chromium driven through
chromedriver and Selenium, and the rule that with GREYBOX_REQUIRE_BROWSER=1 (set by .ci/run)
anything missing is a failure, not a skip."""

import os
from pathlib import Path

import pytest
from browser_support import ROOT, _find, _require


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
