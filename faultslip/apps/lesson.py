"""``faultslip classroom --export lesson.html``: the lesson as one self-contained HTML file that needs no server.

A school's Chromebooks cannot run ``pip install``, so the teacher hands out a file. Everything is inline (its
script, its style, its data) and nothing is fetched, so it opens offline from a USB stick or a shared drive.

- **The student's view** speaks plainly; what the page computes, and where from (seed 003's rate law, its eq.
  2-18, and Table I), is in a "for the teacher" panel, with the lesson's plan and the teacher's guide
  (``docs/teaching_guide.md``) named.
- **The single slider** computes in the browser. Seed 003's rate law gives the static friction at the pull's
  loading rate K V / W, and the exact cycle of :mod:`faultslip.dynamics.spring_slider.exact_cycle` (damped
  sinusoids and a safeguarded Newton iteration for the end of slip, nothing time-stepped) is ported line for
  line to JavaScript. The controls (surfaces, spring, weight, pull speed, mass, damping) move on log scales and
  read in physical units; their defaults are the served app's (``faultslip classroom``). They redraw the
  sawtooth, the phase plane and the numbers; a student reads a period off the sawtooth and checks it, or fits one
  period (one slip's start to the next's). A test in headless Chromium checks the numbers against Python to
  1e-9 (``tests/capabilities/apps/test_lesson_page.py``).
- **The chain of blocks** comes precomputed: :func:`faultslip.apps.classroom.chain_lab` for a few settings of
  coupling and spread. Each catalogue downloads as CSV; the students build its Gutenberg-Richter plot, choosing
  the smallest magnitude they trust and fitting b (Aki's maximum likelihood), and the page says so where the
  catalogue fails faultslip's Gutenberg-Richter test.

Drawing is plain ``<canvas>``: no plotting library, so the file stays small (well under the 5 MB limit).
"""

from __future__ import annotations

import copy
import functools
import html
import json
import math

from faultslip.apps.classroom import chain_lab, stick_slip_presets
from faultslip.friction.materials import STANDARD_GRAVITY, get_preset
from faultslip.io.atomic import write_text_atomic

#: (coupling k_c / k_p, spread of the static limits) of the precomputed chains, 50 blocks, 200 events each
CHAIN_SETTINGS = ((10.0, 0.5), (10.0, 0.2), (2.0, 0.5), (30.0, 0.5))
#: the file's ceiling (issue 45): a lesson handed out by e-mail or on a shared drive
MAX_BYTES = 5 * 1024 * 1024


def lesson_data() -> dict:
    """What the page carries (computed once a process: the chains take seconds): each stick-slip preset's rate law and apparatus (SI), and the precomputed chains.

    Returns
    -------
    dict
        ``presets`` (name -> mu_so, mu_m, b, d, stiffness N/m, normal load N, mass kg = W / g) and ``chains`` (a
        list of {coupling, spread, b, interval, magnitudes, system_events, recurrence_cv}).
    """
    return copy.deepcopy(_lesson_data())


@functools.lru_cache(maxsize=1)
def _lesson_data() -> dict:
    presets = {}
    for name in stick_slip_presets():
        preset = get_preset(name)
        law = preset.require_stick_slip()
        presets[name] = {"mu_so": law.mu_so, "mu_m": law.mu_m, "b": law.b, "d": law.d, "stiffness": preset.stiffness,
                         "normal_load": preset.normal_load, "mass": preset.normal_load / STANDARD_GRAVITY}
    chains = []
    for coupling, spread in CHAIN_SETTINGS:
        lab = chain_lab(blocks=50, coupling_ratio=coupling, spread=spread, events=200)
        b = lab["b"]
        magnitudes = [round(float(m), 4) for m in lab["magnitude"] if math.isfinite(m)]
        chains.append({"coupling": coupling, "spread": spread, "b": None if b is None else b["b"],
                       "interval": None if b is None else list(b["interval"]),
                       "completeness": None if b is None else b["completeness"], "a": None if b is None else b["a"],
                       "magnitudes": magnitudes, "system_events": lab["system_events"],
                       "recurrence_cv": lab["recurrence_cv"]})
    return {"presets": presets, "chains": chains}


def lesson_html(data: dict | None = None) -> str:
    """The page's text (see the module).

    Parameters
    ----------
    data : dict, optional
        :func:`lesson_data`'s (computed when not given).

    Returns
    -------
    str
        One HTML document with its script, style and data inline.
    """
    data = lesson_data() if data is None else data
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")  # no "</script>" inside the script
    options = "".join(f'<option value="{html.escape(name)}"{" selected" if name == "glass_dry" else ""}>'
                      f'{html.escape(plain_name(name))}</option>' for name in data["presets"])
    chains = "".join(f'<option value="{k}">springs between blocks {c["coupling"]:g} times the pulling spring, '
                     f'blocks differing by ±{c["spread"] * 100:.0f} %</option>' for k, c in enumerate(data["chains"]))
    return PAGE.replace("@@OPTIONS@@", options).replace("@@CHAINS@@", chains).replace("@@DATA@@", payload).replace(
        "@@SCRIPT@@", SCRIPT)


def plain_name(preset: str) -> str:
    """A preset's name as a student reads it: "glass_dry" -> "glass, dry", "steel_light_petrolatum" ->
    "steel, light petrolatum"."""
    material, _, condition = preset.partition("_")
    return f"{material}, {condition.replace('_', ' ')}" if condition else material


def export_lesson(path) -> int:
    """Write the lesson page to ``path`` atomically; returns its size in bytes.

    Parameters
    ----------
    path : str or path
        The HTML file.

    Returns
    -------
    int
        Bytes written (at most :data:`MAX_BYTES`).
    """
    text = lesson_html()
    size = len(text.encode("utf-8"))
    if size > MAX_BYTES:  # a guard on this module's own output, not on user input
        raise RuntimeError(f"the lesson page came to {size} bytes, above its {MAX_BYTES}-byte ceiling")
    write_text_atomic(path, text)
    return size


PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Stick and slip: how faults make earthquakes</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
body { font-family: sans-serif; max-width: 960px; margin: 0.6em auto; padding: 0 0.8em; color: #222; }
h1 { font-size: 1.35em; margin: 0.3em 0; } h2 { font-size: 1.1em; margin: 1.2em 0 0.4em; }
.knobs { display: grid; grid-template-columns: 11em minmax(8em, 1fr) 9em; gap: 0.25em 0.8em; align-items: center;
         max-width: 40em; }
canvas { border: 1px solid #ccc; margin: 0.3em 0.3em 0 0; max-width: 100%; height: auto; }
.numbers span { font-weight: bold; } .numbers { margin: 0.5em 0; } small { color: #555; }
details { background: #f6f6f2; border: 1px solid #ddd; padding: 0.3em 0.8em; margin: 1em 0; }
button { margin: 0.2em 0.4em 0.2em 0; } .warning { color: #a33; }
</style></head><body>
<h1>Stick and slip: how faults make earthquakes</h1>
<p>A block is pulled across a table through a spring. It sticks, the spring stretches, and then it slips all at
once: a small earthquake. Faults do the same, far more slowly. Change one control at a time and watch what
happens. <b>Predict first, then try.</b></p>
<h2>1. One block on a spring</h2>
<div class="knobs">
<label for="preset">surfaces</label><select id="preset">@@OPTIONS@@</select><span></span>
<label for="stiffness">spring stiffness</label><input id="stiffness" type="range" min="3" max="7" step="0.01"><output id="stiffness_out"></output>
<label for="load">weight pressing down</label><input id="load" type="range" min="0" max="4" step="any"><output id="load_out"></output>
<label for="pull">pulling speed</label><input id="pull" type="range" min="-1" max="3.5" step="0.01" value="1.30"><output id="pull_out"></output>
<label for="mass">mass of the block</label><input id="mass" type="range" min="-2" max="2" step="0.01"><output id="mass_out"></output>
<label for="damping">damping (0: none)</label><input id="damping" type="range" min="0" max="0.9" step="0.01" value="0.02"><output id="damping_out"></output>
</div>
<div class="numbers">the block <span id="regime"></span> · each slip moves it <span id="slip"></span>
 · the spring's swing <span id="amplitude"></span> · time between slips <span id="period"></span>
 · friction at the start of a slip <span id="mu_s"></span></div>
<canvas id="sawtooth" width="600" height="230"></canvas><canvas id="phase" width="300" height="230"></canvas>
<p><small>Left: the pull of the spring over four cycles. It climbs while the block sticks and drops when it
slips (a sawtooth). Right: one slip, how far the block has moved against how fast it moves; the red line is
the block riding along at the pulling speed.</small></p>
<p>Measure it: read the time between two slips off the left graph and type it here
<input id="guess" type="number" step="any" min="0" style="width:7em"> ms <button id="check">check my reading</button>
<button id="fit">fit one period</button> <span id="period_fit"></span></p>
<h2>2. A fault made of many blocks</h2>
<p>Fifty blocks joined by springs, each stuck to the table until its spring pulls hard enough, make a
catalogue of 200 earthquakes of many sizes. Pick one:</p>
<select id="chain">@@CHAINS@@</select> <button id="csv">download this catalogue (CSV)</button>
<div class="numbers">large earthquakes (all blocks slip) <span id="system_events"></span>
 · how regular they are (0: a clock) <span id="cv"></span></div>
<p>Build the Gutenberg–Richter plot: how many earthquakes are at least as large as each size. Slide the
smallest size you trust, then fit a straight line; its slope is b.</p>
<div class="knobs"><label for="mc">smallest size counted</label><input id="mc" type="range" step="0.01"><output id="mc_out"></output></div>
<button id="gr_fit">fit the line</button>
<div class="numbers">your b <span id="student_b"></span> <span id="gr_warning" class="warning"></span></div>
<div class="numbers">faultslip's b <span id="b_value"></span></div>
<canvas id="mfd" width="600" height="250"></canvas>
<h2>Questions: predict, then test</h2>
<ol><li>Pull more slowly. Will the sawtooth grow or shrink? Try it. Why?</li>
<li>Make the spring much stiffer, or pull much faster. What happens to the stick and the slip?</li>
<li>Press harder on the block (more weight). Do the slips get bigger or smaller? By how much?</li>
<li>In the fault of many blocks, which setting gives the most large earthquakes? Which gives the steepest line
(the highest b)? Can you forecast when the next large one comes?</li></ol>
<details id="teacher"><summary>For the teacher</summary>
<p>The page computes everything itself, offline: the static friction's rate law of seed 003 (its eq. 2-18,
mu_s - mu_m = drop / (1 + drop b rate^d), with the surfaces' constants from its Table I) at the loading rate
K V / W, and the exact stick-slip cycle (damped sinusoids, nothing time-stepped), the numbers
<code>faultslip</code> computes in Python (checked to 1e-9 in its tests). The chains are
<code>configs/spring_chain.toml</code>'s model, computed in advance; faultslip's b is its maximum-likelihood
fit above the completeness magnitude, withheld where the catalogue fails its Gutenberg–Richter test.</p>
<p>A 45-50 minute lesson: 5 min the demonstration (a block, a rubber band, sandpaper), 15 min section 1 with
predictions 1-3, 15 min section 2 with its CSV and the plot, 10 min discussion of question 4: size and timing
are not the same question. The teacher's guide, with the expected answers and the NGSS performance expectations
it serves (MS-ESS2-2, MS-ESS3-2, HS-ESS2-1, HS-ESS3-1), is the page "Teaching with the lesson"
(<code>docs/teaching_guide.md</code>) of faultslip's documentation.</p>
</details>
<script id="data" type="application/json">@@DATA@@</script>
<script>@@SCRIPT@@</script>
</body></html>
"""

#: The page's script: the rate law and the exact cycle (a line-for-line port of exact_cycle.py), and the drawing.
SCRIPT = r"""
"use strict";
const DATA = JSON.parse(document.getElementById("data").textContent);
const EPS = 2.220446049250313e-16;

function staticExcess(rate, p) {  // seed 003 eq. 2-18: mu_s - mu_m = drop / (1 + drop b rate^d)
  const drop = p.mu_so - p.mu_m;
  return drop / (1.0 + drop * p.b * Math.pow(rate, p.d));
}

function oscillator(zeta, u0, v0) {  // U'' + 2 zeta U' + U = 0 from (U0, V0): coefficients of U, U', U''
  const w = Math.sqrt(1.0 - zeta * zeta);
  const a0 = -2.0 * zeta * v0 - u0;
  const j0 = -2.0 * zeta * a0 - v0;
  return {zeta: zeta, omega: w, u: [u0, (v0 + zeta * u0) / w], v: [v0, (a0 + zeta * v0) / w],
          a: [a0, (j0 + zeta * a0) / w]};
}

function damped(osc, which, s) {
  const c = osc[which];
  return Math.exp(-osc.zeta * s) * (c[0] * Math.cos(osc.omega * s) + c[1] * Math.sin(osc.omega * s));
}

function firstZero(osc, which, includeZero) {  // smallest s > 0 (or >= 0) where p cos(w s) + q sin(w s) = 0
  const c = osc[which];
  const phase = Math.atan2(c[1], c[0]);
  const k = Math.ceil((-phase - Math.PI / 2) / Math.PI);
  const s = (phase + Math.PI / 2 + k * Math.PI) / osc.omega;
  const tooEarly = s < 0 || (!includeZero && s <= 0);
  return tooEarly ? s + Math.PI / osc.omega : s;
}

function endOfSlip(osc, target, lo, hi) {  // U'(s) = target on [lo, hi], in delta = T - s (see exact_cycle.py)
  const zeta = osc.zeta, omega = osc.omega, period = 2.0 * Math.PI / omega;
  const pv = osc.v[0], qv = osc.v[1], pa = osc.a[0], qa = osc.a[1];
  const offset = pv - target;
  function residualAndSlope(delta) {
    const phase = omega * delta, cos = Math.cos(phase), sin = Math.sin(phase);
    const decayMinusOne = Math.expm1(zeta * (delta - period));
    const envelope = decayMinusOne + 1.0;
    const cosMinusOne = decayMinusOne * cos - 2.0 * Math.pow(Math.sin(0.5 * phase), 2);
    const residual = target * cosMinusOne + offset * envelope * cos - qv * envelope * sin;
    return [residual, -(envelope * (pa * cos - qa * sin))];
  }
  let dLo = period - hi, dHi = period - lo;
  const fLo = residualAndSlope(dLo)[0], fHi = residualAndSlope(dHi)[0];
  let x = fLo > fHi ? dLo + fLo * (dHi - dLo) / (fLo - fHi) : 0.5 * (dLo + dHi);
  if (!isFinite(x)) { x = 0.0; }
  x = Math.min(Math.max(x, dLo), dHi);
  for (let i = 0; i < 100; i++) {
    const rs = residualAndSlope(x), f = rs[0], slope = rs[1];
    if (f > 0) { dLo = x; } else { dHi = x; }
    const newton = x - f / slope;
    const inside = newton >= dLo && newton <= dHi && slope < 0;
    const xNew = inside ? newton : 0.5 * (dLo + dHi);
    const step = Math.abs(xNew - x);
    x = xNew;
    const scale = Math.max(Math.abs(x), 2.2250738585072014e-308);
    if (!(step > 4 * EPS * scale && dHi - dLo > 4 * EPS * scale && f !== 0)) { break; }
  }
  return [period - x, x];
}

function displacementAt(osc, delta) {
  const period = 2.0 * Math.PI / osc.omega;
  const envelope = Math.exp(osc.zeta * (delta - period));
  return envelope * (osc.u[0] * Math.cos(osc.omega * delta) - osc.u[1] * Math.sin(osc.omega * delta));
}

function displacementDrop(osc, u0, delta) {  // U(0) - U(T - delta) without cancellation
  const period = 2.0 * Math.PI / osc.omega, phase = osc.omega * delta;
  const decayMinusOne = Math.expm1(osc.zeta * (delta - period));
  const envelope = decayMinusOne + 1.0;
  const oneMinus = -decayMinusOne * Math.cos(phase) + 2.0 * Math.pow(Math.sin(0.5 * phase), 2);
  return (u0 - osc.u[0]) + (osc.u[0] * oneMinus + osc.u[1] * envelope * Math.sin(phase));
}

function exactCycle(rate, load, stiffness, mass, excess, zeta) {  // exact_cycle_arrays, for one slider (zeta >= 0)
  const omegaN = Math.sqrt(stiffness / mass), length = load * excess / stiffness;
  const eps = rate / (omegaN * excess);
  const u0 = 1.0 - 2.0 * zeta * eps;
  const osc = oscillator(zeta, u0, eps);
  const sVmin = firstZero(osc, "a", false), sVmax = sVmin + Math.PI / osc.omega;
  const vMax = damped(osc, "v", sVmax);
  const result = {eps: eps, omegaN: omegaN, length: length, osc: osc};
  if (!(vMax >= eps)) { result.regime = "steady_sliding"; return result; }
  const end = endOfSlip(osc, eps, sVmin, sVmax);
  const sUmax = firstZero(osc, "v", true), sUmin = sUmax + Math.PI / osc.omega;
  const uDrop = displacementDrop(osc, u0, end[1]);
  const stick = uDrop / (eps * omegaN), slip = end[0] / omegaN;
  const speed = eps * omegaN * length;
  result.regime = "stick_slip";
  result.amplitude = length * (damped(osc, "u", sUmax) - damped(osc, "u", sUmin));
  result.stickDuration = stick; result.slipDuration = slip; result.period = stick + slip;
  result.slipPerEvent = speed * (stick + slip); result.sEnd = end[0]; result.uEnd = displacementAt(osc, end[1]);
  return result;
}

function el(id) { return document.getElementById(id); }
function show(id, value, unit, digits) {
  const node = el(id);
  node.dataset.value = String(value);
  node.textContent = isFinite(value) ? value.toPrecision(digits || 4) + (unit ? " " + unit : "") : "–";
}

function axes(ctx, canvas, xs, ys, label) {
  const w = canvas.width, h = canvas.height, m = 44;
  ctx.clearRect(0, 0, w, h);
  ctx.strokeStyle = "#999"; ctx.strokeRect(m, 8, w - m - 8, h - m - 8);
  ctx.fillStyle = "#333"; ctx.font = "11px sans-serif"; ctx.fillText(label, m + 4, h - 10);
  const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
  const sx = (w - m - 16) / ((x1 - x0) || 1), sy = (h - m - 24) / ((y1 - y0) || 1);
  const mapX = (x) => m + 4 + (x - x0) * sx, mapY = (y) => h - m - 4 - (y - y0) * sy;
  ctx.fillStyle = "#555";  // the range of each axis, at its ends
  ctx.fillText(x0.toPrecision(3), mapX(x0), h - m + 10); ctx.textAlign = "right";
  ctx.fillText(x1.toPrecision(3), mapX(x1), h - m + 10); ctx.fillText(y0.toPrecision(3), m - 2, mapY(y0));
  ctx.fillText(y1.toPrecision(3), m - 2, mapY(y1) + 8); ctx.textAlign = "left";
  return [mapX, mapY];
}

function line(ctx, xs, ys, map, colour, width) {
  ctx.beginPath(); ctx.strokeStyle = colour; ctx.lineWidth = width || 1.5;
  for (let i = 0; i < xs.length; i++) {
    const px = map[0](xs[i]), py = map[1](ys[i]);
    if (i === 0) { ctx.moveTo(px, py); } else { ctx.lineTo(px, py); }
  }
  ctx.stroke();
}

function physical(id) { return Math.pow(10, +el(id).value); }

function slider() {
  const p = DATA.presets[el("preset").value];
  const stiffness = physical("stiffness"), load = physical("load"), speed = physical("pull") * 1e-6;
  const mass = physical("mass"), zeta = +el("damping").value;
  el("stiffness_out").textContent = stiffness.toPrecision(3) + " N/m";
  el("load_out").textContent = load.toPrecision(3) + " N";
  el("pull_out").textContent = (speed * 1e6).toPrecision(3) + " µm/s";
  el("mass_out").textContent = mass.toPrecision(3) + " kg";
  el("damping_out").textContent = zeta.toFixed(2);
  const rate = stiffness * speed / load;  // theta_dot = K V / W (seed eq. 2-3)
  const excess = staticExcess(rate, p);
  const c = exactCycle(rate, load, stiffness, mass, excess, zeta);
  el("regime").textContent = c.regime === "stick_slip" ? "stick slip" : "steady sliding";
  show("mu_s", p.mu_m + excess, "", 6);
  show("amplitude", c.regime === "stick_slip" ? c.amplitude * 1e6 : NaN, "µm");
  show("period", c.regime === "stick_slip" ? c.period * 1e3 : NaN, "ms");
  show("slip", c.regime === "stick_slip" ? c.slipPerEvent * 1e6 : NaN, "µm");
  el("amplitude").dataset.si = String(c.amplitude); el("period").dataset.si = String(c.period);
  el("slip").dataset.si = String(c.slipPerEvent);
  const saw = el("sawtooth").getContext("2d"), phase = el("phase").getContext("2d");
  SAW = null; el("period_fit").textContent = "";
  if (c.regime !== "stick_slip") {
    saw.clearRect(0, 0, 600, 230); phase.clearRect(0, 0, 300, 230);
    saw.fillText("it slides smoothly: no sticking at this speed and spring", 60, 115); return;
  }
  // one cycle in the dimensionless variables: stick from U_end up to U0 at speed eps, then the slip
  const osc = c.osc, n = 120, slipU = [], slipV = [], slipS = [];
  for (let i = 0; i <= n; i++) { const s = c.sEnd * i / n; slipS.push(s); slipU.push(damped(osc, "u", s));
    slipV.push(damped(osc, "v", s)); }
  const stickTime = (osc.u[0] - c.uEnd) / c.eps;
  const t = [], u = [];
  for (let k = 0; k < 4; k++) {
    const t0 = k * (stickTime + c.sEnd);
    t.push(t0); u.push(c.uEnd); t.push(t0 + stickTime); u.push(osc.u[0]);
    for (let i = 0; i <= n; i++) { t.push(t0 + stickTime + slipS[i]); u.push(slipU[i]); }
  }
  const force = u.map((x) => (x * c.length * stiffness) + load * p.mu_m);
  const tms = t.map((s) => s / c.omegaN * 1e3);
  const map = axes(saw, el("sawtooth"), tms, force, "time (ms) → spring's pull (N) ↑");
  line(saw, tms, force, map, "#1f77b4");
  SAW = {t: tms, force: force, map: map, period: c.period * 1e3};
  const px = slipU.map((x) => x * c.length * 1e6), pv = slipV.map((v) => v * c.length * c.omegaN * 1e3);
  const pmap = axes(phase, el("phase"), px.concat([0]), pv.concat([speed * 1e3]), "moved (µm) → speed (mm/s) ↑");
  line(phase, px, pv, pmap, "#1f77b4");
  line(phase, [px[n], px[0]], [speed * 1e3, speed * 1e3], pmap, "#d62728", 3);
}

let SAW = null;

function peaks(values) {  // where each slip starts: the first sample of each visit to the sawtooth's top
  const high = Math.max(...values), low = Math.min(...values), near = 1e-9 * (high - low), out = [];
  for (let i = 0; i < values.length; i++) {
    if (values[i] >= high - near && (i === 0 || values[i - 1] < high - near)) { out.push(i); }
  }
  return out;
}

function fitOnePeriod() {  // one period read off the drawn sawtooth: from one slip's start to the next's
  if (SAW === null) { el("period_fit").textContent = "no sawtooth to fit"; return NaN; }
  const top = peaks(SAW.force);
  const fitted = SAW.t[top[1]] - SAW.t[top[0]];
  el("period_fit").dataset.value = String(fitted);
  el("period_fit").textContent = "fitted period " + fitted.toPrecision(4) + " ms (first slip to the next)";
  return fitted;
}

function checkReading() {
  const guess = +el("guess").value;
  if (SAW === null || !(guess > 0)) { el("period_fit").textContent = "type a time in ms first"; return; }
  const off = (guess - SAW.period) / SAW.period * 100;
  el("period_fit").textContent = "your reading is " + Math.abs(off).toFixed(1) + " % " + (off > 0 ? "long" : "short");
  const ctx = el("sawtooth").getContext("2d"), top = peaks(SAW.force);
  ctx.strokeStyle = "#2ca02c"; ctx.setLineDash([4, 3]);
  for (let k = 0; k < 4; k++) {
    const x = SAW.map[0](SAW.t[top[0]] + k * guess);
    ctx.beginPath(); ctx.moveTo(x, 8); ctx.lineTo(x, 190); ctx.stroke();
  }
  ctx.setLineDash([]);
}

function catalogueCsv(c) {
  const rows = ["event,magnitude"];
  c.magnitudes.forEach((m, i) => rows.push((i + 1) + "," + m));
  return rows.join("\n") + "\n";
}

function downloadCsv() {
  const c = DATA.chains[+el("chain").value];
  const link = document.createElement("a");
  link.href = URL.createObjectURL(new Blob([catalogueCsv(c)], {type: "text/csv"}));
  link.download = "catalogue_coupling" + c.coupling + "_spread" + Math.round(c.spread * 100) + ".csv";
  document.body.appendChild(link); link.click(); link.remove();
}

function studentB(c, mc) {  // Aki (1965): b = log10(e) / (mean M - Mc), over the magnitudes at or above Mc
  const above = c.magnitudes.filter((m) => m >= mc);
  const mean = above.reduce((a, b) => a + b, 0) / above.length;
  const b = Math.LOG10E / (mean - mc);
  return {b: b, error: b / Math.sqrt(above.length), count: above.length, a: Math.log10(above.length) + b * mc};
}

function drawMfd(fitLine) {
  const c = DATA.chains[+el("chain").value];
  const m = c.magnitudes.slice().sort((a, b) => a - b), count = m.map((_, i) => Math.log10(m.length - i));
  const ctx = el("mfd").getContext("2d");
  const map = axes(ctx, el("mfd"), m, count, "size (magnitude) → log10 of how many are this large or larger ↑");
  ctx.fillStyle = "#1f77b4";
  for (let i = 0; i < m.length; i++) { ctx.fillRect(map[0](m[i]) - 1.5, map[1](count[i]) - 1.5, 3, 3); }
  if (fitLine) {
    const mc = +el("mc").value, fit = studentB(c, mc), x1 = m[m.length - 1];
    line(ctx, [mc, x1], [fit.a - fit.b * mc, fit.a - fit.b * x1], map, "#d62728", 2);
  }
}

function fitGr() {
  const c = DATA.chains[+el("chain").value], mc = +el("mc").value, fit = studentB(c, mc);
  el("student_b").dataset.value = String(fit.b);
  el("student_b").textContent = fit.b.toFixed(2) + " ± " + fit.error.toFixed(2) + " (" + fit.count + " earthquakes)";
  el("gr_warning").textContent = c.b === null ? "but these sizes do not follow the Gutenberg–Richter law: the " +
    "points do not lie on one straight line, so a b-value does not describe them" : "";
  drawMfd(true);
}

function chain() {
  const c = DATA.chains[+el("chain").value];
  if (c.b === null) {  // the catalogue failed the Gutenberg-Richter test: no b to show
    el("b_value").dataset.value = "";
    el("b_value").textContent = "none: these magnitudes do not follow Gutenberg–Richter (see the plot)";
  } else {
    show("b_value", c.b, "", 3);
    el("b_value").textContent += c.interval ? " (" + c.interval[0].toFixed(2) + "–" + c.interval[1].toFixed(2) + ")" : "";
  }
  el("system_events").textContent = String(c.system_events); show("cv", c.recurrence_cv, "", 2);
  const low = Math.min(...c.magnitudes), high = Math.max(...c.magnitudes);
  el("mc").min = low.toFixed(2); el("mc").max = high.toFixed(2);
  el("mc").value = (c.completeness !== null ? c.completeness : low).toFixed(2);
  el("mc_out").textContent = "magnitude " + (+el("mc").value).toFixed(2);
  el("student_b").textContent = ""; el("gr_warning").textContent = "";
  drawMfd(false);
}

function start() {
  const p = DATA.presets[el("preset").value];
  el("stiffness").value = Math.log10(p.stiffness).toFixed(2); el("mass").value = Math.log10(p.mass).toFixed(2);
  el("load").value = String(Math.log10(p.normal_load));  // the surfaces' own load, exactly (step "any")
  slider();
}
for (const id of ["stiffness", "load", "pull", "mass", "damping"]) { el(id).addEventListener("input", slider); }
el("preset").addEventListener("change", start);
el("chain").addEventListener("change", chain);
el("mc").addEventListener("input", () => { el("mc_out").textContent = "magnitude " + (+el("mc").value).toFixed(2); });
el("gr_fit").addEventListener("click", fitGr);
el("csv").addEventListener("click", downloadCsv);
el("fit").addEventListener("click", fitOnePeriod);
el("check").addEventListener("click", checkReading);
start(); chain();
"""
