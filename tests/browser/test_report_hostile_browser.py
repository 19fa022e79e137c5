"""A report built from a hostile study directory, in a real headless browser: SVGs that
would set `window.pwned` (onload, <script>, <img onerror> in a foreignObject, a
javascript: link, <set>/<animate> handlers, an element with id="pwned") run nothing, the
page's own frame slider still works under the page's Content-Security-Policy, and the
browser logs no error (a blocked script would be one).

Runs when chromium, chromedriver and selenium are installed; with GREYBOX_REQUIRE_BROWSER=1
(set by .ci/run) their absence is a failure, not a skip.
"""

import json
import subprocess
import time
from pathlib import Path

import pytest
from browser_support import browser, greybox_exe  # noqa: F401 (fixtures)

PLOT = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="300" height="150" viewBox="0 0 300 150">'
    '<rect width="300" height="150" fill="white"/>'
    '<polyline fill="none" stroke="black" points="0,0 150,75 300,30"/>'
    "<text x=\"10\" y=\"20\">frame {k}</text></svg>"
)

HOSTILE = {
    "forces.svg": '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" onload="window.pwned=1">'
    '<script>window.pwned = 1</script><rect id="pwned" width="100" height="100" fill="red"/></svg>',
    "profile_stress.svg": '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
    '<foreignObject width="100" height="100"><img xmlns="http://www.w3.org/1999/xhtml" '
    'src="x" onerror="window.pwned=1"/></foreignObject>'
    '<image href="x" width="10" height="10" onerror="window.pwned=1"/></svg>',
    "profile_velocity.svg": '<svg xmlns="http://www.w3.org/2000/svg" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" width="100" height="100">'
    '<a xlink:href="javascript:window.pwned=1"><rect id="link" width="100" height="100"/></a></svg>',
    "profile_temperature.svg": '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
    '<rect width="100" height="100"><set attributeName="onmouseover" to="window.pwned=1"/>'
    '<animate attributeName="x" from="0" to="1" dur="0.1s" onbegin="window.pwned=1"/></rect>'
    '<style>@import url("javascript:window.pwned=1");</style></svg>',
    "chip_temperature.svg": '<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x '
    '"&#60;script&#62;window.pwned=1&#60;/script&#62;">]>'
    '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100"><text y="20">&x;</text>'
    "<script><![CDATA[window.pwned = 1]]></script></svg>",
}


@pytest.fixture(scope="module")
def hostile_report(tmp_path_factory, greybox_exe) -> tuple[Path, dict]:
    study = tmp_path_factory.mktemp("hostile") / "study"
    cut = study / "cut"
    (cut / "frames").mkdir(parents=True)
    (cut / "summary.json").write_text(json.dumps({"cutting_force_n_per_mm": 201.5}))
    for name, svg in HOSTILE.items():
        (cut / name).write_text(svg)
    for k in (1, 2, 3):
        (cut / "frames" / f"chip_00{k}.svg").write_text(PLOT.format(k=k))
    (cut / "frames" / "chip_004.svg").write_text(HOSTILE["forces.svg"])
    run = subprocess.run(
        [str(greybox_exe), "--quiet", "report", str(study), "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    return study / "report.html", json.loads(run.stdout)


def test_hostile_svgs_run_nothing_and_the_slider_still_works(hostile_report, browser):
    page, summary = hostile_report
    removed = [w for w in summary["warnings"] if "elements/attributes removed from" in w]
    assert len(removed) == len(HOSTILE) + 1, summary["warnings"]

    browser.get(page.as_uri())
    # give load/error handlers and animations the chance to fire, and hover and click
    # where the hostile figures were
    time.sleep(1.0)
    for el in browser.find_elements("css selector", "figure svg"):
        try:
            el.click()
        except Exception:  # hidden frames cannot be clicked
            pass
    time.sleep(0.3)
    assert browser.execute_script("return typeof window.pwned") == "undefined"
    assert browser.execute_script("return document.querySelectorAll('script').length") == 1

    # the page's own script ran (the controls are shown by it) and the slider works
    state = browser.execute_script(
        """
        const box = document.querySelector('figure.frames');
        const slider = box.querySelector('input');
        slider.value = 2;
        slider.dispatchEvent(new Event('input'));
        const frames = [...box.querySelectorAll(':scope > .frame')];
        return {n: frames.length, shown: frames.map(f => !f.hidden),
                label: box.querySelector('output').textContent,
                controls: !box.querySelector('.controls').hidden};
        """
    )
    assert state["controls"], "the page's own script did not run (blocked by the CSP?)"
    assert state["n"] == 4
    assert state["shown"] == [False, True, False, False]
    assert state["label"] == "frame 2 of 4"

    errors = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert errors == [], errors
