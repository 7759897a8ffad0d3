"""``faultslip classroom``: an interactive stick-slip lab in the browser, served locally by Bokeh.

Why Bokeh server: it is a well-kept data-app framework (NumFOCUS) whose Python callbacks run the
library itself on every knob change and push only the new data to the page; its JavaScript is served
from the installed package, so the app works offline, with no CDN for scripts or fonts; and its page
models can be driven from a test browser by name. Panel sits on top of Bokeh and would add a second
layer without adding a view this app needs.

Three views, each a tab:

1. **The slider lab**: a Table I preset with knobs for the spring, the pull speed, the mass, the damping
   and the friction law. The sawtooth, the phase plane and an animated block on its platform change
   together; the regime, the amplitude and the period are printed with the method that computed them
   (:func:`faultslip.models.solve`, exact where it can be: microseconds).
2. **Stick-slip to earthquakes**: the same slider at fault scale (:class:`faultslip.models.Fault`): lithology,
   G, the elastic zone, the stress and the slip rate give the slip per event, the recurrence and Mw; one
   button loads the seed's 1906 San Francisco example.
3. **Your own experiment**: a phyphox CSV, checked like every input (one sentence for a bad file), read
   and analysed as ``faultslip record`` does, with the lesson's questions beside it.
4. **A fault of many blocks**: the spring-block chain (``configs/spring_chain.toml``) with knobs for the
   number of blocks, the coupling and the spread of the static limits: its catalogue, its
   magnitude-frequency distribution with Aki's b-value and interval, and the predictability test.

The physics lives in pure functions (:func:`slider_lab`, :func:`earthquake`, :func:`experiment`,
:func:`chain_lab`) that the tests and the benchmark call without a browser.
"""

from __future__ import annotations

import base64
import html
import ipaddress
import math
from pathlib import Path

import numpy as np

import faultslip
from faultslip.dynamics.methods import solve
from faultslip.dynamics.spring_slider.critical import critical
from faultslip.dynamics.spring_slider.exact_cycle import slip_trajectory
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.errors import FaultslipError, InputError
from faultslip.io.uploads import scratch_copy
from faultslip.fault.scaling import Fault
from faultslip.fault.scene import read_slider_scene
from faultslip.friction.laws import ConstantStatic
from faultslip.friction.materials import presets
from faultslip.io.resources import config_path, parse_toml, read_text_file
from faultslip.lab.classroom import analyse, read_accelerometer
from faultslip.models import parse_chain_scene
from faultslip.units import JULIAN_YEAR

LAWS = {"rate": "static friction rises as the loading rate falls (seed eq. 2-18)",
        "constant": "constant static friction (Coulomb)"}
QUESTIONS = (
    "How does the friction drop mu_s - mu_k compare from one slip to the next? What would make it vary?",
    "Pull more slowly: does the sawtooth in the slider lab grow or shrink? Does your phone agree?",
    "The band's omega gives k/m. Weigh the phone: what is the band's stiffness in N/m?",
    "The slider lab's regime turns to steady sliding above a critical pull speed. Can you find it with the phone?",
    "Scale up: with the 1906 button, how many centuries does the fault 'stick' between slips?",
)


def stick_slip_presets() -> list[str]:
    """The Table I presets that stick and slip (and so have an apparatus)."""
    return sorted(name for name, preset in presets().items() if preset.stick_slip and preset.normal_load)


def slider_lab(preset: str = "glass_dry", stiffness: float | None = None, pull_speed: float = 2e-5,
               mass: float | None = None, damping_ratio: float = 0.02, law: str = "rate", cycles: int = 4) -> dict:
    """The slider's limit cycle and its time series for the lab view, in SI.

    Returns ``time``, ``spring_force``, ``displacement`` (of the slider against the platform's frame) and
    ``platform`` over ``cycles`` cycles; the phase-plane ``x`` and ``v`` of one cycle; and ``regime``,
    ``amplitude`` (peak-to-peak displacement), ``period``, ``method``, ``method_reason`` and the critical
    pull speed."""
    if law not in LAWS:
        raise InputError(f"the friction law must be one of {', '.join(LAWS)}, got {law!r}")
    system = SliderSystem.from_preset(preset, platform_speed=f"{pull_speed!r} m/s", damping_ratio=0.0,
                                      stiffness=None if stiffness is None else f"{stiffness!r} N/m")
    if mass is not None:
        if not (math.isfinite(mass) and mass > 0):
            raise InputError(f"the mass must be positive, got {mass!r} kg")
        system = system.with_(mass=mass)
    if not 0 <= damping_ratio < 1:
        raise InputError(f"the damping ratio must be from 0 to below 1, got {damping_ratio!r}")
    system = system.with_(dashpot=2.0 * damping_ratio * math.sqrt(system.stiffness * system.mass))
    if law == "constant":
        system = system.with_(static_law=ConstantStatic(system.static_law.mu_so))
    solution = solve(system, cycles=cycles + 2)
    cycle = solution.cycle
    speed = system.platform_speed
    critical_speed = math.nan
    try:
        critical_rate = critical(system).critical_loading_rate
        critical_speed = critical_rate * system.normal_load / system.stiffness
    except FaultslipError:
        pass
    period = float(cycle.period) if cycle.period is not None else math.nan
    out = {"regime": cycle.regime, "amplitude": float(cycle.amplitude), "period": period,
           "method": solution.method, "method_reason": solution.method_reason, "pull_speed": speed,
           "critical_pull_speed": critical_speed, "natural_frequency": system.natural_frequency,
           "stiffness": system.stiffness, "mass": system.mass, "preset": preset, "law": law,
           "estimated_relative_error": float(solution.estimated_relative_error)}
    if cycle.regime == "stick_slip" and math.isfinite(period) and period > 0:
        slip_time, x_slip, v_slip = slip_trajectory(system, samples=200)
        stick = period - (slip_time[-1] - slip_time[0])
        # one cycle: stick (x' = V, the spring stretches) from the re-stick point, then the slip
        stick_t = np.linspace(0.0, stick, 60)
        t_cycle = np.concatenate([stick_t, stick + (slip_time - slip_time[0])])
        x_cycle = np.concatenate([x_slip[-1] + speed * stick_t, x_slip])
        v_cycle = np.concatenate([np.full(stick_t.size, speed), v_slip])
        out["x"], out["v"] = x_slip, v_slip
        out["stick_x"] = [float(x_slip[-1]), float(x_slip[0])]
    else:  # steady sliding (or an oscillation that decays into it): the trajectory from a small kick
        duration = 8 * 2 * math.pi / system.natural_frequency
        t_cycle, x_cycle, v_cycle = slip_trajectory(system, duration=duration, samples=400)
        t_cycle = t_cycle - t_cycle[0]
        out["x"], out["v"] = x_cycle, v_cycle
        out["stick_x"] = []
        period = duration
    repeats = cycles if cycle.regime == "stick_slip" else 1
    time = np.concatenate([t_cycle + k * period for k in range(repeats)])
    x = np.tile(x_cycle, repeats)
    out["time"], out["displacement"] = time, x
    out["spring_force"] = system.stiffness * x
    out["platform"] = speed * time
    return out


def earthquake(lithology: str = "granodiorite", shear_modulus: float = 3e10, zone_width: float = 20e3,
               shear_stress: float = 2.5e7, slip_rate: float = 0.05 / JULIAN_YEAR, rupture_length: float = 430e3,
               seismogenic_depth: float = 12e3) -> dict:
    """The fault view: seed 003 §5-2 scaling through :class:`faultslip.models.Fault` (SI in); slip per event (m),
    recurrence (s) and Mw, with the method that computed them."""
    fault = Fault(slip_rate=f"{slip_rate!r} m/s", zone_width=f"{zone_width!r} m",
                  shear_modulus=f"{shear_modulus!r} Pa", shear_stress=f"{shear_stress!r} Pa", lithology=lithology,
                  rupture_length=f"{rupture_length!r} m", seismogenic_depth=f"{seismogenic_depth!r} m",
                  name="classroom fault")
    estimate = fault.estimate()
    return {"slip_per_event": float(estimate.slip_per_event), "recurrence_period": float(estimate.recurrence_period),
            "moment_magnitude": float(estimate.moment_magnitude) if estimate.moment_magnitude is not None
            else math.nan, "regime": estimate.regime, "method": estimate.method,
            "normal_stress": float(estimate.normal_stress)}


def scene_1906() -> dict:
    """The seed's 1906 San Francisco example (configs/san_andreas_1906.toml) as the fault view's knobs (SI)."""
    fault = read_slider_scene(config_path("san_andreas_1906.toml")).fault()
    return {"lithology": fault.lithology, "shear_modulus": fault.shear_modulus, "zone_width": fault.zone_width,
            "shear_stress": fault.shear_stress, "slip_rate": fault.slip_rate, "rupture_length": fault.rupture_length,
            "seismogenic_depth": fault.seismogenic_depth}


def experiment(content: bytes, filename: str = "upload.csv") -> dict:
    """A phyphox (or accelerometer) CSV's analysis, as ``faultslip record`` gives it: the detected slips,
    mu_s - mu_k, the pull speed and the traces to draw. A bad file raises :class:`InputError`."""
    suffix = Path(filename).suffix.lower() or ".csv"
    if suffix not in (".csv", ".txt"):
        raise InputError(f"{filename!r} is not a CSV export: phyphox's 'Export data' gives a .csv file")
    with scratch_copy(content, suffix) as path:
        try:
            record = read_accelerometer(path)
            result = analyse(record)
        except InputError as exc:  # name the student's file, not the temporary copy
            raise InputError(str(exc).replace(f"'{path}'", repr(filename)).replace(path.name, filename)) from None
    signal = record.acceleration[result.axis]
    report = result.report().to_dict()
    return {"time": record.time, "acceleration": signal - float(np.median(signal)), "axis": result.axis,
            "starts": result.starts, "durations": result.durations, "friction_drop": result.friction_drop,
            "events": int(result.starts.size), "report": report, "filename": filename}


# --- the Bokeh document ------------------------------------------------------------------------------------

def chain_lab(blocks: int = 50, coupling_ratio: float = 10.0, spread: float = 0.5, events: int = 200) -> dict:
    """The classroom's chain: ``configs/spring_chain.toml`` with its blocks, coupling and spread changed.

    Parameters
    ----------
    blocks : int
        Number of blocks (1 to 100).
    coupling_ratio : float
        k_c / k_p.
    spread : float
        The spread of the static limits (0 to 0.9).
    events : int
        Events to run.

    Returns
    -------
    dict
        ``start`` (s), ``first`` and ``last`` block of each event, ``magnitude``, ``b`` (the b-value's dict or
        None), ``system_events``, ``recurrence_cv``, ``predictability`` (:func:`faultslip.hazard.predictability`) and
        ``slip_after``: each event's total slip with the interval that follows it.
    """
    if not (isinstance(blocks, (int, np.integer)) and 1 <= blocks <= 100):
        raise InputError(f"the classroom chain has 1 to 100 blocks, got {blocks!r}")
    path = config_path("spring_chain.toml")
    document = parse_toml(read_text_file(path, "spring-block chain scene"), path.name)
    leaf = parse_chain_scene(document, path.name).chain.leaf_stiffness
    document["chain"].update(blocks=int(blocks), threshold_spread=float(spread),
                             coupling_stiffness=f"{float(coupling_ratio) * leaf!r} N/m")
    document["run"]["events"] = int(events)
    loaded = parse_chain_scene(document, path.name)
    run = faultslip.models.simulate_chain(loaded.chain, loaded.events, initial_position=loaded.initial_position)
    stats = faultslip.models.chain_statistics(loaded, run)
    first, last = run.extents()
    return {"start": run.start, "first": first, "last": last, "magnitude": stats["magnitude"], "b": stats["b"],
            "b_reason": stats.get("b_reason", ""),
            "system_events": stats["system_events"], "recurrence_cv": stats["recurrence_cv"],
            "predictability": faultslip.hazard.predictability(run.start, run.total_slip),
            "slip_after": (run.total_slip[:-1], np.diff(run.start))}


def _text(value) -> str:
    """Anything that reaches the page from a run or an upload (a file's name, its header, an error quoting its
    cells) as text, never as markup: the status panels render HTML."""
    return html.escape(str(value), quote=True)


def _fmt(value, unit="", digits=4):
    return "–" if value is None or not math.isfinite(value) else f"{value:.{digits}g}{(' ' + unit) if unit else ''}"


#: The block, its spring and the platform, stepped through the sawtooth's samples 20 times a second (BokehJS).
ANIMATION = """
let frame = 0;
setInterval(() => {
  const data = saw.data;
  const get = (key) => (data instanceof Map) ? data.get(key) : data[key];
  const x = get('x'), t = get('t');
  if (!x || x.length === 0) { return; }
  const n = x.length;
  const step = Math.max(1, Math.floor(n / 120));
  const i = frame % n; frame += step;
  let lo = Infinity, hi = -Infinity, sum = 0;
  for (const v of x) { lo = Math.min(lo, v); hi = Math.max(hi, v); sum += v; }
  const span = Math.max(hi - lo, 1e-12);
  const bx = Math.max(-0.9, Math.min(0.9, (x[i] - sum / n) / span * 0.6));
  block.data = {x: [bx], y: [0.45]};
  const xs = [], ys = [];
  for (let k = 0; k < 25; k++) {
    xs.push(-1.1 + (bx - 0.15 + 1.1) * k / 24);
    ys.push(0.45 + ((k > 0 && k < 24) ? 0.08 * Math.sin(10 * Math.PI * k / 24) : 0));
  }
  spring.data = {x: xs, y: ys};
  marker.data = {x: [t[i] / Math.max(t[n - 1], 1e-30) * 2.0 - 1.0], y: [0.05]};
}, 50);
"""


def make_document(doc) -> None:
    """Build the four views into a Bokeh document (the server calls this for each browser session)."""
    from bokeh.layouts import column, row  # heavy: Bokeh loads only when the app is served
    from bokeh.models import (Button, ColumnDataSource, Div, FileInput, Select, Slider,  # heavy: as above
                              TabPanel, Tabs)
    from bokeh.events import DocumentReady  # heavy: as above
    from bokeh.models import CustomJS  # heavy: as above
    from bokeh.plotting import figure  # heavy: as above

    # 1. the slider lab
    preset_names = stick_slip_presets()
    base = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s")
    preset = Select(title="material preset (seed Table I)", value="glass_dry", options=preset_names, name="preset")
    law = Select(title="friction law", value="rate", options=[(k, v) for k, v in LAWS.items()], name="law")
    stiffness = Slider(title="spring stiffness k (log10 N/m)", start=3.0, end=7.0, step=0.05,
                       value=round(math.log10(base.stiffness), 2), name="stiffness")
    pull = Slider(title="pull speed V (log10 µm/s)", start=-1.0, end=3.5, step=0.05, value=1.3, name="pull_speed")
    mass = Slider(title="mass m (log10 kg)", start=-2.0, end=2.0, step=0.05, value=round(math.log10(base.mass), 2),
                  name="mass")
    damping = Slider(title="damping ratio ζ", start=0.0, end=0.9, step=0.01, value=0.02, name="damping")
    saw_source = ColumnDataSource(data={"t": [], "force": [], "x": []}, name="sawtooth_source")
    phase_source = ColumnDataSource(data={"x": [], "v": []}, name="phase_source")
    stick_source = ColumnDataSource(data={"x": [], "v": []}, name="stick_source")
    block_source = ColumnDataSource(data={"x": [0.0], "y": [0.5]}, name="block_source")
    spring_source = ColumnDataSource(data={"x": [], "y": []}, name="spring_source")
    marker_source = ColumnDataSource(data={"x": [0.0], "y": [1.0]}, name="platform_marker")
    saw = figure(height=260, sizing_mode="stretch_width", title="sawtooth: spring force",
                 x_axis_label="time (ms)", y_axis_label="spring force k x (N)", name="sawtooth")
    saw.line("t", "force", source=saw_source, line_width=2)
    phase = figure(height=260, width=360, title="phase plane", x_axis_label="x (µm)", y_axis_label="x' (mm/s)",
                   name="phase")
    phase.line("x", "v", source=phase_source, line_width=2, legend_label="slip")
    phase.line("x", "v", source=stick_source, line_width=3, color="firebrick", legend_label="stick (x' = V)")
    phase.legend.location = "bottom_left"
    stage = figure(height=180, sizing_mode="stretch_width", title="the block, its spring and the moving platform",
                   x_range=(-1.2, 1.2), y_range=(-0.2, 1.6), toolbar_location=None, name="stage")
    stage.xaxis.visible = stage.yaxis.visible = False
    stage.quad(left=-1.2, right=1.2, bottom=-0.1, top=0.2, color="#bbbbbb")
    stage.scatter("x", "y", source=marker_source, marker="triangle", size=14, color="#555555")
    stage.rect("x", "y", width=0.3, height=0.5, source=block_source, color="steelblue")
    stage.line("x", "y", source=spring_source, line_width=2, color="darkorange")
    status = Div(text="", name="lab_status", width=900, height=48)  # fixed: a new text re-lays out nothing

    def redraw(attr, old, new):
        try:
            lab = slider_lab(preset.value, stiffness=10 ** stiffness.value, pull_speed=10 ** pull.value * 1e-6,
                             mass=10 ** mass.value, damping_ratio=damping.value, law=law.value)
        except FaultslipError as exc:
            status.text = f"<b style='color:#b00'>{_text(exc)}</b>"
            return
        saw_source.data = {"t": lab["time"] * 1e3, "force": lab["spring_force"], "x": lab["displacement"] * 1e6}
        phase_source.data = {"x": np.asarray(lab["x"]) * 1e6, "v": np.asarray(lab["v"]) * 1e3}
        stick_source.data = ({"x": [v * 1e6 for v in lab["stick_x"]], "v": [lab["pull_speed"] * 1e3] * 2}
                             if lab["stick_x"] else {"x": [], "v": []})
        critical_text = _fmt(lab["critical_pull_speed"] * 1e6, "µm/s")
        status.text = (f"<b>regime: {_text(lab['regime'].replace('_', ' '))}</b> · amplitude "
                       f"{_fmt(lab['amplitude'] * 1e6, 'µm')} · period {_fmt(lab['period'] * 1e3, 'ms')} · "
                       f"critical pull speed {critical_text}<br><small>method: {_text(lab['method'])} "
                       f"({_text(lab['method_reason'])}); declared error {lab['estimated_relative_error']:.1g}</small>")

    for widget in (preset, law):
        widget.on_change("value", redraw)
    for widget in (stiffness, pull, mass, damping):
        widget.on_change("value_throttled", redraw)  # on release; a drag redraws once, not per pixel
    redraw(None, None, None)
    # the animation runs in the browser, from the sawtooth already there: no server traffic between knob changes
    doc.js_on_event(DocumentReady, CustomJS(args=dict(saw=saw_source, block=block_source, spring=spring_source,
                                                      marker=marker_source), code=ANIMATION))
    lab_view = column(row(column(preset, law, stiffness, pull, mass, damping, width=320), phase),
                      status, saw, stage, sizing_mode="stretch_width")

    # 2. stick-slip to earthquakes
    lithologies = sorted({p.lithology for p in presets().values() if p.lithology and p.stick_slip})
    quake_inputs = {
        "lithology": Select(title="lithology", value="granodiorite", options=lithologies, name="lithology"),
        "shear_modulus": Slider(title="shear modulus G (GPa)", start=5, end=60, step=0.5, value=30, name="G"),
        "zone_width": Slider(title="elastic zone width D (km)", start=1, end=60, step=0.5, value=20, name="D"),
        "shear_stress": Slider(title="shear stress τ (bar)", start=10, end=1000, step=5, value=250, name="tau"),
        "slip_rate": Slider(title="slip rate (mm/yr)", start=1, end=100, step=0.5, value=50, name="slip_rate"),
        "rupture_length": Slider(title="rupture length (km)", start=10, end=1000, step=5, value=430, name="L"),
        "seismogenic_depth": Slider(title="seismogenic depth (km)", start=5, end=25, step=0.5, value=12, name="H")}
    button = Button(label="the seed's 1906 San Francisco example", button_type="primary", name="load_1906")
    quake_status = Div(text="", name="quake_status", sizing_mode="stretch_width")

    def quake(attr, old, new):
        q = quake_inputs
        try:
            result = earthquake(q["lithology"].value, q["shear_modulus"].value * 1e9, q["zone_width"].value * 1e3,
                                q["shear_stress"].value * 1e5, q["slip_rate"].value * 1e-3 / JULIAN_YEAR,
                                q["rupture_length"].value * 1e3, q["seismogenic_depth"].value * 1e3)
        except FaultslipError as exc:
            quake_status.text = f"<b style='color:#b00'>{_text(exc)}</b>"
            return
        quake_status.text = (f"<h3>slip per event {_fmt(result['slip_per_event'], 'm', 3)} · recurrence "
                             f"{_fmt(result['recurrence_period'] / JULIAN_YEAR, 'yr', 4)} · Mw "
                             f"{_fmt(result['moment_magnitude'], '', 3)}</h3><small>regime "
                             f"{_text(result['regime'].replace('_', ' '))}; method {_text(result['method'])}; normal stress "
                             f"τ/μso = {_fmt(result['normal_stress'] / 1e5, 'bar')}</small>")

    def load_1906():
        scene = scene_1906()
        values = {"shear_modulus": scene["shear_modulus"] / 1e9, "zone_width": scene["zone_width"] / 1e3,
                  "shear_stress": scene["shear_stress"] / 1e5, "slip_rate": scene["slip_rate"] * JULIAN_YEAR * 1e3,
                  "rupture_length": scene["rupture_length"] / 1e3,
                  "seismogenic_depth": scene["seismogenic_depth"] / 1e3}
        for key, value in values.items():
            quake_inputs[key].value = round(float(value), 6)
        if scene["lithology"] in lithologies:
            quake_inputs["lithology"].value = scene["lithology"]
        quake(None, None, None)

    for key, widget in quake_inputs.items():
        widget.on_change("value_throttled" if isinstance(widget, Slider) else "value", quake)
    button.on_click(load_1906)
    quake(None, None, None)
    quake_view = column(button, row(column(*list(quake_inputs.values())[:4]), column(*list(quake_inputs.values())[4:])),
                        quake_status, sizing_mode="stretch_width")

    # 3. your own experiment
    upload = FileInput(accept=".csv,.txt", name="upload")
    upload_status = Div(text="Drop in a phyphox export (Acceleration without g, CSV).", name="upload_status",
                        sizing_mode="stretch_width")
    trace_source = ColumnDataSource(data={"t": [], "a": []}, name="trace_source")
    slips_source = ColumnDataSource(data={"left": [], "right": [], "bottom": [], "top": []}, name="slips_source")
    trace = figure(height=280, sizing_mode="stretch_width", title="acceleration along the pull; slips shaded",
                   x_axis_label="time (s)", y_axis_label="acceleration (m/s²)", name="trace")
    trace.quad(left="left", right="right", bottom="bottom", top="top", source=slips_source, color="firebrick",
               alpha=0.2)
    trace.line("t", "a", source=trace_source, line_width=1)
    questions = Div(text="<h4>Questions</h4><ol>" + "".join(f"<li>{q}</li>" for q in QUESTIONS) + "</ol>",
                    sizing_mode="stretch_width")

    def uploaded(attr, old, new):
        try:
            result = experiment(base64.b64decode(upload.value), upload.filename or "upload.csv")
        except FaultslipError as exc:
            upload_status.text = f"<b style='color:#b00'>{_text(exc)}</b>"
            trace_source.data = {"t": [], "a": []}
            slips_source.data = {"left": [], "right": [], "bottom": [], "top": []}
            return
        except (ValueError, TypeError):
            upload_status.text = "<b style='color:#b00'>the upload could not be read as a file</b>"
            return
        trace_source.data = {"t": result["time"], "a": result["acceleration"]}
        reach = 1.1 * float(np.max(np.abs(result["acceleration"]))) if result["time"].size else 1.0
        slips_source.data = {"left": result["starts"], "right": result["starts"] + result["durations"],
                             "bottom": np.full(result["starts"].size, -reach), "top": np.full(result["starts"].size, reach)}
        r = result["report"]
        if result["events"]:
            upload_status.text = (f"<b>{result['events']} slips</b> on axis {_text(result['axis'])} · μs − μk "
                                  f"{_fmt(r['friction_drop'], '', 3)} (median) · pull speed "
                                  f"{_fmt(r['pull_speed']['value'] * 1e3, 'mm/s', 3)} · slip duration "
                                  f"{_fmt(r['slip_duration']['value'], 's', 3)}")
        else:
            upload_status.text = f"no slip found in {_text(result['filename'])}: pull more slowly, or press the phone down"

    upload.on_change("filename", uploaded)
    experiment_view = column(upload, upload_status, trace, questions, sizing_mode="stretch_width")

    # 4. a fault of many blocks
    chain_blocks = Slider(title="blocks", start=1, end=100, step=1, value=50, name="chain_blocks")
    chain_coupling = Slider(title="coupling k_c / k_p", start=0.0, end=30.0, step=0.5, value=10.0,
                            name="chain_coupling")
    chain_spread = Slider(title="spread of the static limits", start=0.0, end=0.9, step=0.05, value=0.5,
                          name="chain_spread")
    events_source = ColumnDataSource(data={"t": [], "first": [], "last": []}, name="chain_events_source")
    mfd_source = ColumnDataSource(data={"m": [], "n": []}, name="chain_mfd_source")
    gr_source = ColumnDataSource(data={"m": [], "n": []}, name="chain_gr_source")
    pred_source = ColumnDataSource(data={"slip": [], "after": []}, name="chain_pred_source")
    catalogue = figure(height=260, sizing_mode="stretch_width", title="the catalogue: blocks each event slipped",
                       x_axis_label="time (s)", y_axis_label="block", name="chain_catalogue")
    catalogue.segment(x0="t", y0="first", x1="t", y1="last", source=events_source, color="firebrick", line_width=2)
    mfd = figure(height=260, width=380, y_axis_type="log", title="magnitude-frequency",
                 x_axis_label="magnitude M", y_axis_label="events with magnitude ≥ M", name="chain_mfd")
    mfd.scatter("m", "n", source=mfd_source, size=4)
    mfd.line("m", "n", source=gr_source, color="firebrick", line_width=2)
    pred = figure(height=260, width=380, title="time-predictable? slip against the wait after it",
                  x_axis_label="slip summed over the blocks (mm)", y_axis_label="interval after (s)",
                  name="chain_predictability")
    pred.scatter("slip", "after", source=pred_source, size=4, color="seagreen")
    chain_status = Div(text="", name="chain_status", width=900, height=60)

    def chain(attr, old, new):
        try:
            lab = chain_lab(int(chain_blocks.value), chain_coupling.value, chain_spread.value)
        except FaultslipError as exc:
            chain_status.text = f"<b style='color:#b00'>{_text(exc)}</b>"
            return
        events_source.data = {"t": lab["start"], "first": lab["first"] - 0.4, "last": lab["last"] + 0.4}
        magnitude = np.sort(lab["magnitude"][np.isfinite(lab["magnitude"])])
        mfd_source.data = {"m": magnitude, "n": np.arange(magnitude.size, 0, -1)}
        b = lab["b"]
        if b is not None:
            line = np.linspace(b["completeness"], magnitude.max(), 20)
            gr_source.data = {"m": line, "n": 10 ** (b["a"] - b["b"] * line)}
        else:
            gr_source.data = {"m": [], "n": []}
        slip, after = lab["slip_after"]
        pred_source.data = {"slip": slip * 1e3, "after": after}
        found = lab["predictability"]
        verdicts = ", ".join(name.replace("_", "-") for name, held in found.verdicts.items() if held) or "none"
        b_text = (f"b = {b['b']:.3g} ({b['interval'][0]:.3g}–{b['interval'][1]:.3g})" if b is not None else
                  "no b-value: " + _text(lab.get("b_reason") or "every event the same size"))
        chain_status.text = (f"<b>{b_text}</b> · {lab['system_events']} system-size events, their CV "
                             f"{_fmt(lab['recurrence_cv'], '', 2)} · r(slip, interval after) "
                             f"{found.time_correlation:.2f}<br><small>models the catalogue supports: "
                             f"{_text(verdicts)}</small>")

    for widget in (chain_blocks, chain_coupling, chain_spread):
        widget.on_change("value_throttled", chain)
    chain(None, None, None)
    chain_view = column(row(column(chain_blocks, chain_coupling, chain_spread, width=320), mfd, pred), chain_status,
                        catalogue, sizing_mode="stretch_width")
    doc.add_root(Tabs(tabs=[TabPanel(child=lab_view, title="The slider lab"),
                            TabPanel(child=quake_view, title="Stick-slip to earthquakes"),
                            TabPanel(child=experiment_view, title="Your own experiment"),
                            TabPanel(child=chain_view, title="A fault of many blocks")], name="tabs",
                       sizing_mode="stretch_width"))
    doc.title = "faultslip classroom"


def check_address(address) -> str:
    """The address to serve on: an IPv4 or IPv6 literal, or ``localhost``; anything else is one sentence."""
    text = str(address).strip()
    if text.startswith("[") and text.endswith("]"):
        text = text[1:-1]
    if text == "localhost":
        return text
    try:
        parsed = ipaddress.ip_address(text)
    except ValueError:
        raise InputError(f"--address must be an IP address (127.0.0.1, ::1, 0.0.0.0, ::) or localhost, got "
                         f"{str(address)!r}") from None
    if parsed.version == 6 and not (parsed.is_loopback or parsed.is_unspecified):
        raise InputError(f"--address {text}: an IPv6 server is reached as localhost, so it serves on ::1 or :: "
                         "(every interface); for another IPv6 address give a host name that resolves to it")
    return str(parsed)


def serve(port: int = 5006, address: str = "127.0.0.1", open_browser: bool = False, announce=print) -> None:
    """Serve the app until interrupted; ``announce`` receives its address first."""
    from bokeh.application import Application  # heavy: Bokeh loads only when the app is served
    from bokeh.application.handlers.function import FunctionHandler  # heavy: as above
    from bokeh.server.server import Server  # heavy: as above

    address = check_address(address)
    # Bokeh's websocket-origin list cannot hold an IPv6 literal (it splits host:port at every colon), so an
    # IPv6 server is reached as localhost, which browsers resolve to ::1 as well as 127.0.0.1
    ipv6 = ":" in address
    origins = [f"localhost:{port}", f"127.0.0.1:{port}"] + ([] if ipv6 else [f"{address}:{port}"])
    server = Server({"/": Application(FunctionHandler(make_document))}, port=port, address=address,
                    allow_websocket_origin=origins, num_procs=1)
    server.start()
    url = f"http://{'localhost' if ipv6 or address in ('127.0.0.1', '0.0.0.0') else address}:{server.port}/"
    announce(url)
    if open_browser:
        import webbrowser  # a platform module: only when asked to open a browser

        server.io_loop.add_callback(lambda: webbrowser.open(url))
    server.io_loop.start()
