"""The classroom app: its physics without a browser, then the real thing in headless Chromium.

The browser tests start ``faultslip classroom`` as a process and drive it through the page's BokehJS
models (faultslip.apps.browser). They are skipped, with the reason, only where no Chromium can run
(.ci/run installs Debian's chromium and chromium-driver).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

import faultslip
from faultslip.apps import browser
from faultslip.apps.classroom import earthquake, experiment, scene_1906, slider_lab
from faultslip.errors import InputError
from faultslip.units import JULIAN_YEAR

EXAMPLE = "configs/example_phyphox.csv"
ROOT = Path(__file__).resolve().parents[3]


def test_the_lab_follows_the_seeds_trend_and_its_critical_speed():
    """Seed 003 Fig. 3: the stick-slip amplitude grows as the loading rate falls; above the critical pull speed
    the slider slides steadily. The lab view says which method computed it."""
    speeds = [2e-6, 5e-6, 2e-5]
    labs = [slider_lab("glass_dry", pull_speed=v) for v in speeds]
    amplitudes = [lab["amplitude"] for lab in labs]
    assert all(lab["regime"] == "stick_slip" for lab in labs) and amplitudes == sorted(amplitudes, reverse=True)
    critical = labs[0]["critical_pull_speed"]
    assert slider_lab("glass_dry", pull_speed=1.2 * critical)["regime"] == "steady_sliding"
    assert labs[0]["method"] == "exact_cycle" and labs[0]["estimated_relative_error"] < 1e-6
    # the sawtooth repeats with the period it reports, and the force is k x
    lab = labs[1]
    assert lab["time"][-1] == pytest.approx(4 * lab["period"], rel=1e-9)
    np.testing.assert_allclose(lab["spring_force"], lab["stiffness"] * lab["displacement"])
    # a stiffer spring at the same speed: a shorter, smaller cycle
    stiffer = slider_lab("glass_dry", pull_speed=5e-6, stiffness=4 * lab["stiffness"])
    assert stiffer["amplitude"] < labs[1]["amplitude"]
    with pytest.raises(InputError):
        slider_lab("glass_dry", law="stribeck")


def test_the_fault_view_is_the_fault_command(cli):
    scene = scene_1906()
    view = earthquake(**scene)
    out = cli("run", "--json").json  # the default scene is the 1906 example
    assert view["slip_per_event"] == pytest.approx(out["slip_per_event"]["value"], rel=1e-12)
    assert view["recurrence_period"] == pytest.approx(out["recurrence_period"]["value"], rel=1e-12)
    assert view["moment_magnitude"] == pytest.approx(out["moment_magnitude"], abs=1e-12)
    assert 100 < view["recurrence_period"] / JULIAN_YEAR < 200


def test_the_experiment_view_is_the_record_command(cli):
    with open(EXAMPLE, "rb") as handle:
        view = experiment(handle.read(), "example_phyphox.csv")
    out = cli("record", EXAMPLE, "--json").json
    assert view["events"] == out["events"]
    assert view["report"]["friction_drop"] == pytest.approx(out["friction_drop"], rel=1e-12)
    for bad, words in ((b"", "is empty"), (b"time;x\n1;2\n", "example.csv"), (b"\xff\xfe\x00", "UTF-8")):
        with pytest.raises(InputError, match=words) as caught:
            experiment(bad, "example.csv")
        assert "\n" not in str(caught.value) and "/tmp" not in str(caught.value)


# --- in a real browser ---------------------------------------------------------------------------------------

needs_browser = pytest.mark.skipif(browser.missing() is not None, reason=str(browser.missing()))


@pytest.fixture(scope="module")
def page():
    with browser.running_app() as url, browser.chromium() as driver:
        browser.open_app(driver, url)
        yield driver


def _status(driver, name):
    return browser.model_value(driver, name, "text")


def _amplitude(text):
    value = text.split("amplitude ")[1].split(" µm")[0]
    return float(value)


@needs_browser
def test_moving_the_pull_speed_knob_redraws_as_the_physics_says(page, tmp_path):
    amplitudes = []
    for log_speed in (1.0, 0.3):  # 10 then 2 um/s (the page starts at 20)
        before = _status(page, "lab_status")
        browser.set_knob(page, "pull_speed", log_speed)
        browser.wait_for(page, f"return Bokeh.documents[0].get_model_by_name('lab_status').text !== {before!r};")
        text = _status(page, "lab_status")
        amplitudes.append(_amplitude(text))
        expected = slider_lab("glass_dry", pull_speed=10 ** log_speed * 1e-6,
                              stiffness=10 ** browser.model_value(page, "stiffness", "value"),
                              mass=10 ** browser.model_value(page, "mass", "value"), damping_ratio=0.02)
        assert amplitudes[-1] == pytest.approx(expected["amplitude"] * 1e6, rel=1e-3)
        forces = browser.column(page, "sawtooth_source", "force")
        assert max(forces) - min(forces) == pytest.approx(np.ptp(expected["spring_force"]), rel=1e-6)
    assert amplitudes[1] > 3 * amplitudes[0]  # slower pull, larger sawtooth (seed Fig. 3)
    page.save_screenshot(str(tmp_path / "lab.png"))
    assert (tmp_path / "lab.png").stat().st_size > 20_000


@needs_browser
def test_uploading_the_phyphox_example_matches_the_cli_and_a_bad_file_is_one_sentence(page, cli, tmp_path):
    import base64

    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 2;")
    with open(EXAMPLE, "rb") as handle:
        payload = base64.b64encode(handle.read()).decode()
    out = cli("record", EXAMPLE, "--json").json
    page.execute_script(f"""const m = Bokeh.documents[0].get_model_by_name('upload');
        m.value = {payload!r}; m.mime_type = 'text/csv'; m.filename = 'example_phyphox.csv';""")
    browser.wait_for(page, "return Bokeh.documents[0].get_model_by_name('upload_status').text.includes('slips');")
    text = _status(page, "upload_status")
    assert f"{out['events']} slips" in text
    assert f"{out['friction_drop']:.3g}" in text and f"{out['pull_speed']['value'] * 1e3:.3g} mm/s" in text
    assert len(browser.column(page, "trace_source", "t")) > 100
    page.save_screenshot(str(tmp_path / "experiment.png"))
    bad = base64.b64encode(b"this is not an accelerometer export\n").decode()
    page.execute_script(f"""const m = Bokeh.documents[0].get_model_by_name('upload');
        m.value = {bad!r}; m.filename = 'holiday.csv';""")
    browser.wait_for(page, "return Bokeh.documents[0].get_model_by_name('upload_status').text.includes('holiday');")
    message = _status(page, "upload_status")
    assert "holiday.csv" in message and "Traceback" not in message and message.count(". ") <= 1
    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 0;")


@needs_browser
def test_the_earthquake_tab_answers_from_its_knobs(page):
    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 1;")
    before = _status(page, "quake_status")
    browser.set_knob(page, "slip_rate", 25.0)  # half the default rate: twice the recurrence
    browser.wait_for(page, f"return Bokeh.documents[0].get_model_by_name('quake_status').text !== {before!r};")
    text = _status(page, "quake_status")
    expected = earthquake("granodiorite", 30e9, 20e3, 250e5, 25e-3 / JULIAN_YEAR, 430e3, 12e3)
    assert f"{expected['recurrence_period'] / JULIAN_YEAR:.4g} yr" in text
    assert not math.isnan(expected["moment_magnitude"])
    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 0;")
    json.dumps(text)


HOSTILE = ['<img src=x onerror="window.__pwned=1">.csv', "<script>window.__pwned=1</script>.csv",
           "\"><svg onload=window.__pwned=1>.csv"]


@needs_browser
@pytest.mark.parametrize("name", HOSTILE)
def test_an_uploaded_name_or_header_never_runs_as_script(page, name):
    """A file named <img src=x onerror=alert(1)>.csv ran script in the page: the status panels render HTML, and
    the name, the header and the cells reached them unescaped. Hostile names and contents go in; the page's DOM
    must hold them as text (no new element, no handler run)."""
    import base64

    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 2; window.__pwned = 0;")
    content = ("time (s),<img src=x onerror=window.__pwned=1> (m/s^2)\n0,<script>window.__pwned=1</script>\n"
               ).encode()
    for payload in (content, b"not a csv <b onmouseover=window.__pwned=1>x</b>\n"):
        page.execute_script(f"""const m = Bokeh.documents[0].get_model_by_name('upload');
            m.value = {base64.b64encode(payload).decode()!r}; m.filename = {name!r};""")
        marker = name[:6]
        browser.wait_for(page, "return Bokeh.documents[0].get_model_by_name('upload_status').text.includes("
                               f"{json.dumps(marker.replace('<', '&lt;').replace('>', '&gt;').replace(chr(34), '&quot;'))});")
        page.execute_script("return new Promise(r => setTimeout(r, 300));")  # let any planted handler fire
        injected = page.execute_script(
            "const roots = [document]; const found = [];"
            "for (const host of document.querySelectorAll('*')) { if (host.shadowRoot) roots.push(host.shadowRoot); }"
            "for (const root of roots) { for (const el of root.querySelectorAll('img, script, svg, b[onmouseover]')) {"
            "  if ((el.outerHTML || '').includes('__pwned')) found.push(el.outerHTML); } }"
            "return found;")
        assert injected == [] and page.execute_script("return window.__pwned") == 0
    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 0;")


def test_the_chain_view_is_the_chain_family():
    """The classroom's chain is configs/spring_chain.toml with its knobs: the same catalogue as faultslip.run."""
    from faultslip.apps.classroom import chain_lab

    lab = chain_lab()
    result = faultslip.run(ROOT / "configs" / "spring_chain.toml")
    # the example chain is not Gutenberg-Richter: neither gives a b-value, and the classroom says why
    assert lab["b"] is None and result["b_value"] is None and "not Gutenberg-Richter" in lab["b_reason"]
    assert lab["system_events"] == result["system_size_events"]
    one = chain_lab(blocks=1, events=20)
    assert one["b"] is None and one["predictability"].verdicts["periodic"]
    with pytest.raises(InputError, match="1 to 100 blocks"):
        chain_lab(blocks=0)


@needs_browser
def test_the_chain_tab_answers_from_its_knobs(page):
    from faultslip.apps.classroom import chain_lab

    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 3;")
    before = _status(page, "chain_status")
    browser.set_knob(page, "chain_blocks", 20)
    browser.wait_for(page, f"return Bokeh.documents[0].get_model_by_name('chain_status').text !== {before!r};")
    text = _status(page, "chain_status")
    expected = chain_lab(blocks=20)
    assert (f"b = {expected['b']['b']:.3g}" in text if expected["b"] is not None
            else "no b-value" in text and "Gutenberg-Richter" in text)
    assert len(browser.column(page, "chain_events_source", "t")) == 200
    assert len(browser.column(page, "chain_mfd_source", "m")) == np.isfinite(expected["magnitude"]).sum()
    page.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 0;")
