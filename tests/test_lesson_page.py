"""The lesson page that needs no server (issue 45, item 4): one self-contained file, opened offline in headless
Chromium, its knobs moved, its numbers checked against Python's exact cycle to 1e-9."""

from __future__ import annotations

import math

import pytest

from faultslip.apps import browser
from faultslip.apps.lesson import MAX_BYTES, lesson_data, lesson_html
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
from faultslip.dynamics.spring_slider.slider import SliderSystem

from conftest import assert_clean_error

needs_browser = pytest.mark.skipif(browser.missing() is not None, reason=str(browser.missing()))


@pytest.fixture(scope="module")
def data():
    return lesson_data()


@pytest.fixture(scope="module")
def page(data, tmp_path_factory):
    path = tmp_path_factory.mktemp("lesson") / "lesson.html"
    path.write_text(lesson_html(data), encoding="utf-8")
    with browser.chromium() as driver:
        # the network cut: the page must need nothing beyond its own file
        driver.execute_cdp_cmd("Network.enable", {})
        driver.execute_cdp_cmd("Network.emulateNetworkConditions", {"offline": True, "latency": 0,
                                                                    "downloadThroughput": 0, "uploadThroughput": 0})
        driver.get(path.as_uri())
        browser.wait_for(driver, "return document.getElementById('amplitude').dataset.value !== undefined;")
        yield driver


def test_the_file_is_self_contained_and_small(data):
    text = lesson_html(data)
    assert len(text.encode("utf-8")) < MAX_BYTES
    assert "http://" not in text and "https://" not in text and " src=" not in text


def _python(page, preset):
    knobs = page.execute_script("""return ['stiffness', 'pull', 'mass', 'damping'].map(
        (id) => +document.getElementById(id).value);""")
    stiffness, speed, mass, zeta = 10 ** knobs[0], 10 ** knobs[1] * 1e-6, 10 ** knobs[2], knobs[3]
    system = SliderSystem.from_preset(preset, platform_speed=f"{speed!r} m/s", stiffness=f"{stiffness!r} N/m")
    system = system.with_(mass=mass, dashpot=2 * zeta * math.sqrt(stiffness * mass))
    return exact_cycle(system)


def _page_numbers(page):
    return page.execute_script("""const v = (id) => +document.getElementById(id).dataset.si;
        return {regime: document.getElementById('regime').textContent, amplitude: v('amplitude'),
                period: v('period'), slip: v('slip'), mu_s: +document.getElementById('mu_s').dataset.value};""")


@needs_browser
@pytest.mark.parametrize("preset, knobs", [
    ("glass_dry", {}),
    ("glass_dry", {"pull": 0.3, "damping": 0.2}),
    ("steel_dry", {"pull": 2.0, "stiffness": 5.5}),
    ("granodiorite_water", {"mass": 0.5, "damping": 0.05}),
])
def test_the_pages_knobs_agree_with_pythons_exact_cycle(page, preset, knobs):
    page.execute_script(f"""const s = document.getElementById('preset'); s.value = {preset!r};
        s.dispatchEvent(new Event('change'));""")
    for name, value in knobs.items():
        page.execute_script(f"""const k = document.getElementById({name!r}); k.value = {value!r};
            k.dispatchEvent(new Event('input'));""")
    shown = _page_numbers(page)
    expected = _python(page, preset)
    assert shown["regime"].replace(" ", "_") == expected.regime
    if expected.regime == "stick_slip":
        for key, value in (("amplitude", expected.amplitude), ("period", expected.period),
                           ("slip", expected.slip_per_event)):
            assert shown[key] == pytest.approx(value, rel=1e-9), key
        assert shown["mu_s"] == pytest.approx(expected.static_friction, rel=1e-12)
    # nothing was fetched: every resource the page holds is its own file
    assert page.execute_script("return performance.getEntriesByType('resource').length;") == 0


@needs_browser
def test_the_chains_come_precomputed_with_their_b_values(page, data):
    for index, chain in enumerate(data["chains"]):
        page.execute_script(f"""const s = document.getElementById('chain'); s.value = '{index}';
            s.dispatchEvent(new Event('change'));""")
        if chain["b"] is None:  # the catalogue is not Gutenberg-Richter: the page says so, with no b
            text = page.execute_script("return document.getElementById('b_value').textContent;")
            assert "do not follow Gutenberg" in text
            continue
        value = float(page.execute_script("return document.getElementById('b_value').dataset.value;"))
        assert value == pytest.approx(chain["b"], rel=1e-15)
    with_b = [chain for chain in data["chains"] if chain["b"] is not None]
    if len(with_b) >= 2 and {0, 2} <= {data["chains"].index(c) for c in with_b}:
        assert data["chains"][2]["b"] > data["chains"][0]["b"]  # weaker coupling, higher b (docs/classroom.md)


def test_the_export_command_writes_one_file_and_refuses_a_bad_name(cli, tmp_path):
    out = cli("classroom", "--export", tmp_path / "lesson.html")
    assert out.code == 0, out.err
    assert (tmp_path / "lesson.html").stat().st_size < MAX_BYTES
    assert_clean_error(cli("classroom", "--export", tmp_path / "lesson.pdf"), ".html")
    assert_clean_error(cli("classroom", "--export", tmp_path / "lesson.html"), "exists")
