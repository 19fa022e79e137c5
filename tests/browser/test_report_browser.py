"""The demo's report.html in a real headless browser (Debian's chromium through
chromedriver and Selenium): every section and picture renders, no console error, the frame
slider works; the page is valid HTML5 (html5lib, strict) and under 5 MB; a full-page
screenshot is saved.

Runs when chromium, chromedriver and selenium are installed; with GREYBOX_REQUIRE_BROWSER=1
(set by .ci/run) their absence is a failure, not a skip.
"""

import os
import subprocess
from pathlib import Path

import pytest
from browser_support import ROOT, browser, greybox_exe  # noqa: F401 (fixtures)

EXPECTED_SECTIONS = [
    "Campaign",
    "Friction data",
    "Models",
    "Cutting",
    "Rig dynamics and wear",
    "Provenance",
]


@pytest.fixture(scope="module")
def demo_report(tmp_path_factory, greybox_exe) -> Path:
    exe = greybox_exe
    out = tmp_path_factory.mktemp("demo") / "demo-out"
    subprocess.run(
        [str(exe), "--quiet", "demo", "--out", str(out)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    page = out / "report.html"
    assert page.is_file(), "greybox demo wrote no report.html"
    return page


def test_report_is_valid_html5_and_small(demo_report):
    import html5lib

    data = demo_report.read_bytes()
    assert len(data) < 5_000_000, f"report.html is {len(data)} bytes"
    # strict: the first parse error of the HTML5 parsing algorithm raises
    html5lib.HTMLParser(strict=True).parse(data)


def test_report_renders_in_a_real_browser(demo_report, browser):
    from selenium.webdriver.support.ui import WebDriverWait

    browser.get(demo_report.as_uri())

    def headings(driver):
        return [h.text for h in driver.find_elements("css selector", "section > h2")]

    # A loaded machine may hand the page over before its layout is done: wait (at most 30 s)
    # until the sections are laid out, then check them exactly.
    try:
        WebDriverWait(browser, 30).until(lambda d: len(headings(d)) >= len(EXPECTED_SECTIONS))
    except Exception:
        pass
    assert headings(browser) == EXPECTED_SECTIONS
    # every nav link leads to a section
    for a in browser.find_elements("css selector", "nav a"):
        target = a.get_attribute("href").split("#", 1)[1]
        assert browser.find_elements("id", target), target

    # every raster decodes (SVG <image> data and any <img>), every visible figure has a size
    broken = browser.execute_async_script(
        """
        const done = arguments[arguments.length - 1];
        const sources = [...document.querySelectorAll('svg image')].map(i => i.href.baseVal)
            .concat([...document.querySelectorAll('img')].map(i => i.src));
        Promise.all(sources.map(src => new Promise(ok => {
            const im = new Image();
            im.onload = () => ok(im.naturalWidth > 0 && im.naturalHeight > 0 ? null : src.slice(0, 60));
            im.onerror = () => ok(src.slice(0, 60));
            im.src = src;
        }))).then(r => done({count: sources.length, broken: r.filter(x => x)}));
        """
    )
    assert broken["broken"] == [], broken
    assert broken["count"] >= 4, broken  # 2 chip pictures + frames
    empty = browser.execute_script(
        """
        return [...document.querySelectorAll('figure svg')]
            .filter(s => !s.closest('[hidden]'))
            .filter(s => { const r = s.getBoundingClientRect(); return !(r.width > 50 && r.height > 50); })
            .length;
        """
    )
    assert empty == 0
    figures = browser.execute_script("return document.querySelectorAll('figure').length")
    assert figures >= 20

    # the frame slider shows one frame at a time
    state = browser.execute_script(
        """
        const box = document.querySelector('.frames');
        const slider = box.querySelector('input');
        slider.value = 1;
        slider.dispatchEvent(new Event('input'));
        const frames = [...box.querySelectorAll('.frame')];
        return {n: frames.length, shown: frames.map(f => !f.hidden),
                label: box.querySelector('output').textContent,
                controls: !box.querySelector('.controls').hidden};
        """
    )
    assert state["n"] >= 2 and state["controls"]
    assert state["shown"] == [True] + [False] * (state["n"] - 1)
    assert state["label"] == f"frame 1 of {state['n']}"

    errors = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert errors == [], errors

    # a full-page screenshot for people to look at
    metrics = browser.execute_cdp_cmd("Page.getLayoutMetrics", {})
    size = metrics["cssContentSize"]
    shot = browser.execute_cdp_cmd(
        "Page.captureScreenshot",
        {
            "format": "png",
            "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": size["width"], "height": size["height"], "scale": 1},
        },
    )
    import base64

    dest = Path(os.environ.get("GREYBOX_SCREENSHOT", ROOT / "target" / "report-screenshot.png"))
    dest.parent.mkdir(parents=True, exist_ok=True)
    dest.write_bytes(base64.b64decode(shot["data"]))
    assert dest.stat().st_size > 10_000
