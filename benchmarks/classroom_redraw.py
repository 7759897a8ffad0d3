"""How fast the classroom app redraws after a knob change, on the server and in the browser (issue 31).

- **Server side**: the slider lab's computation (:func:`faultslip.apps.classroom.slider_lab`, what the
  knob's callback runs) for 60 knob settings across presets, pull speeds (stick-slip and steady sliding),
  springs and masses: median and 95th percentile.
- **In the browser**: ``faultslip classroom`` served locally, driven in headless Chromium. A script sets
  a knob through the page's BokehJS model (what a drag does) and times, with the page's own clock,
  until the new sawtooth data has arrived from the server and until the next frame after it has been
  painted: median and 95th percentile over 30 changes. The target is 100 ms.

It also takes the screenshots of docs/classroom.md (docs/figures/classroom_*.png).

    python benchmarks/classroom_redraw.py       # about a minute; needs Chromium (apt-get install chromium chromium-driver)
"""

from __future__ import annotations

import base64
import json
import sys
import time
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent

TIMED_CHANGE = """
const done = arguments[arguments.length - 1];
const doc = Bokeh.documents[0];
const source = doc.get_model_by_name('sawtooth_source');
const knob = doc.get_model_by_name(arguments[0]);
const before = source.data;
const start = performance.now();
knob.value = arguments[1]; knob.value_throttled = arguments[1];
function check() {
  if (source.data !== before) {
    const arrived = performance.now() - start;
    requestAnimationFrame(() => done([arrived, performance.now() - start]));
  } else if (performance.now() - start > 10000) { done(null); }
  else { setTimeout(check, 1); }
}
check();
"""


def main() -> int:
    from faultslip.apps import browser
    from faultslip.apps.classroom import slider_lab, stick_slip_presets

    rng = np.random.default_rng(3)
    slider_lab()  # the first call loads what every later one shares
    server = []
    for _ in range(60):
        preset = str(rng.choice(stick_slip_presets()))
        started = time.perf_counter()
        slider_lab(preset, pull_speed=10 ** rng.uniform(-6.5, -3.5), damping_ratio=float(rng.uniform(0, 0.3)))
        server.append((time.perf_counter() - started) * 1e3)
    result = {"server_ms": {"median": float(np.median(server)), "p95": float(np.percentile(server, 95)),
                            "settings": len(server)}}
    reason = browser.missing()
    if reason:
        result["browser"] = f"not measured: {reason}"
    else:
        figures = ROOT / "docs" / "figures"
        with browser.running_app() as url, browser.chromium(width=1300, height=1050) as driver:
            browser.open_app(driver, url)
            driver.set_script_timeout(30)
            arrived, painted = [], []
            values = [("pull_speed", v) for v in (0.3, 1.0, 0.5, 1.5, 0.0, 1.2)] + \
                     [("stiffness", v) for v in (6.0, 6.3, 5.8)] + [("damping", v) for v in (0.1, 0.3, 0.05)]
            for index in range(30):
                name, value = values[index % len(values)]
                value = value + 1e-3 * (index // len(values))  # never the knob's current value
                timing = driver.execute_async_script(TIMED_CHANGE, name, value)
                if timing is None:
                    raise RuntimeError(f"no redraw after setting {name} to {value}")
                arrived.append(timing[0])
                painted.append(timing[1])
            result["browser_ms"] = {"data_arrived": {"median": float(np.median(arrived)),
                                                     "p95": float(np.percentile(arrived, 95))},
                                    "painted": {"median": float(np.median(painted)),
                                                "p95": float(np.percentile(painted, 95))}, "changes": len(painted)}
            browser.set_knob(driver, "pull_speed", 0.3)
            time.sleep(1.5)
            driver.save_screenshot(str(figures / "classroom_lab.png"))
            driver.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 1;")
            time.sleep(1.0)
            driver.save_screenshot(str(figures / "classroom_earthquake.png"))
            driver.execute_script("Bokeh.documents[0].get_model_by_name('tabs').active = 2;")
            payload = base64.b64encode((ROOT / "configs" / "example_phyphox.csv").read_bytes()).decode()
            driver.execute_script(f"""const m = Bokeh.documents[0].get_model_by_name('upload');
                m.value = {payload!r}; m.filename = 'example_phyphox.csv';""")
            browser.wait_for(driver, "return Bokeh.documents[0].get_model_by_name('upload_status').text"
                                     ".includes('slips');")
            time.sleep(1.0)
            driver.save_screenshot(str(figures / "classroom_experiment.png"))
        result["screenshots"] = ["docs/figures/classroom_lab.png", "docs/figures/classroom_earthquake.png",
                                 "docs/figures/classroom_experiment.png"]
    result.update(stamp())
    (ROOT / "benchmarks" / "results" / "classroom_redraw.json").write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
