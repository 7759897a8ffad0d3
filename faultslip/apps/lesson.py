"""``faultslip classroom --export lesson.html``: the lesson as one self-contained HTML file that needs no server.

A school's Chromebooks cannot run ``pip install``, so the teacher hands out a file. Everything is inline (its
script, its style, its data) and nothing is fetched, so it opens offline from a USB stick or a shared drive.

- **The single slider** computes in the browser. Seed 003's rate law (eq. 2-18) gives the static friction at
  the pull's loading rate, and the exact cycle of :mod:`faultslip.dynamics.spring_slider.exact_cycle` (damped
  sinusoids and a safeguarded Newton iteration for the end of slip, nothing time-stepped) is ported line for
  line to JavaScript. The knobs (preset, spring, pull speed, mass, damping) redraw the sawtooth, the phase plane
  and the numbers: amplitude, period, slip per event, regime. A test in headless Chromium checks them against
  Python to 1e-9 (``tests/test_lesson_page.py``).
- **The chain of blocks** comes precomputed: :func:`faultslip.apps.classroom.chain_lab` for a few settings of
  coupling and spread, each catalogue's magnitudes and b-value inline, drawn as a magnitude-frequency plot.

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
                      f'{html.escape(name)}</option>' for name in data["presets"])
    chains = "".join(f'<option value="{k}">k_c / k_p = {c["coupling"]:g}, spread ±{c["spread"] * 100:.0f} %</option>'
                     for k, c in enumerate(data["chains"]))
    return PAGE.replace("@@OPTIONS@@", options).replace("@@CHAINS@@", chains).replace("@@DATA@@", payload).replace(
        "@@SCRIPT@@", SCRIPT)


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
<html lang="en"><head><meta charset="utf-8"><title>faultslip lesson: stick-slip to earthquakes</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
body { font-family: sans-serif; max-width: 980px; margin: 1em auto; padding: 0 1em; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
.knobs { display: grid; grid-template-columns: 14em 1fr 8em; gap: 0.3em 0.8em; align-items: center; max-width: 40em; }
canvas { border: 1px solid #ccc; margin: 0.4em 0.4em 0 0; }
.numbers span { font-weight: bold; } .numbers { margin: 0.6em 0; } small { color: #555; }
</style></head><body>
<h1>Stick-slip to earthquakes: a lesson that runs in the browser</h1>
<p><small>Everything here computes in this page, offline: seed 003's static-friction rate law (eq. 2-18) and the
exact stick-slip cycle, the same numbers faultslip computes in Python. Made by <code>faultslip classroom --export</code>.
</small></p>
<h2>1. The slider</h2>
<div class="knobs">
<label for="preset">material (seed Table I)</label><select id="preset">@@OPTIONS@@</select><span></span>
<label for="stiffness">spring stiffness k (log10 N/m)</label><input id="stiffness" type="range" min="3" max="7" step="0.05"><output id="stiffness_out"></output>
<label for="pull">pull speed V (log10 µm/s)</label><input id="pull" type="range" min="-1" max="3.5" step="0.05" value="1.3"><output id="pull_out"></output>
<label for="mass">mass m (log10 kg)</label><input id="mass" type="range" min="-2" max="2" step="0.05"><output id="mass_out"></output>
<label for="damping">damping ratio ζ</label><input id="damping" type="range" min="0" max="0.9" step="0.01" value="0.02"><output id="damping_out"></output>
</div>
<div class="numbers">regime <span id="regime"></span> · amplitude <span id="amplitude"></span> · period <span id="period"></span>
 · slip per event <span id="slip"></span> · static friction <span id="mu_s"></span></div>
<canvas id="sawtooth" width="620" height="240"></canvas><canvas id="phase" width="300" height="240"></canvas>
<p><small>Left: the spring force over four cycles (it climbs while the block sticks and drops when it slips).
Right: the phase plane of one slip, displacement against velocity; the red line is the stick, where the block
rides the platform at V.</small></p>
<h2>2. A fault of many blocks</h2>
<p>Fifty blocks coupled by springs (<code>configs/spring_chain.toml</code>), 200 events each, computed in advance:</p>
<select id="chain">@@CHAINS@@</select>
<div class="numbers">b-value <span id="b_value"></span> · system-size events <span id="system_events"></span>
 · their coefficient of variation <span id="cv"></span></div>
<canvas id="mfd" width="620" height="260"></canvas>
<h2>Questions</h2>
<ol><li>Pull more slowly. Does the sawtooth grow or shrink? Why? (The static friction rises as the loading rate
falls, seed eq. 2-18.)</li>
<li>Make the spring much stiffer, or pull much faster. What happens to the stick-slip?</li>
<li>In the chain, which setting gives the most large events? Which gives the highest b-value?</li></ol>
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

function slider() {
  const p = DATA.presets[el("preset").value];
  const stiffness = Math.pow(10, +el("stiffness").value), speed = Math.pow(10, +el("pull").value) * 1e-6;
  const mass = Math.pow(10, +el("mass").value), zeta = +el("damping").value;
  el("stiffness_out").textContent = stiffness.toPrecision(3) + " N/m";
  el("pull_out").textContent = (speed * 1e6).toPrecision(3) + " µm/s";
  el("mass_out").textContent = mass.toPrecision(3) + " kg";
  el("damping_out").textContent = zeta.toFixed(2);
  const rate = stiffness * speed / p.normal_load;  // theta_dot = K V / W (seed eq. 2-3)
  const excess = staticExcess(rate, p);
  const c = exactCycle(rate, p.normal_load, stiffness, mass, excess, zeta);
  el("regime").textContent = c.regime.replace("_", " ");
  show("mu_s", p.mu_m + excess, "", 6);
  show("amplitude", c.regime === "stick_slip" ? c.amplitude * 1e6 : NaN, "µm");
  show("period", c.regime === "stick_slip" ? c.period * 1e3 : NaN, "ms");
  show("slip", c.regime === "stick_slip" ? c.slipPerEvent * 1e6 : NaN, "µm");
  el("amplitude").dataset.si = String(c.amplitude); el("period").dataset.si = String(c.period);
  el("slip").dataset.si = String(c.slipPerEvent);
  const saw = el("sawtooth").getContext("2d"), phase = el("phase").getContext("2d");
  if (c.regime !== "stick_slip") {
    saw.clearRect(0, 0, 620, 240); phase.clearRect(0, 0, 300, 240);
    saw.fillText("steady sliding: no stick-slip at this pull speed and spring", 60, 120); return;
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
  const force = u.map((x) => (x * c.length * stiffness) + p.normal_load * p.mu_m);
  const tms = t.map((s) => s / c.omegaN * 1e3);
  line(saw, tms, force, axes(saw, el("sawtooth"), tms, force, "time (ms) → spring force (N) ↑"), "#1f77b4");
  const px = slipU.map((x) => x * c.length * 1e6), pv = slipV.map((v) => v * c.length * c.omegaN * 1e3);
  const map = axes(phase, el("phase"), px.concat([0]), pv.concat([speed * 1e3]), "x (µm) → x' (mm/s) ↑");
  line(phase, px, pv, map, "#1f77b4");
  line(phase, [px[n], px[0]], [speed * 1e3, speed * 1e3], map, "#d62728", 3);
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
  const m = c.magnitudes.slice().sort((a, b) => a - b), count = m.map((_, i) => Math.log10(m.length - i));
  const ctx = el("mfd").getContext("2d");
  const map = axes(ctx, el("mfd"), m, count, "magnitude → log10 number with magnitude ≥ M ↑");
  ctx.fillStyle = "#1f77b4";
  for (let i = 0; i < m.length; i++) { ctx.fillRect(map[0](m[i]) - 1.5, map[1](count[i]) - 1.5, 3, 3); }
  if (c.b !== null) {
    const x0 = c.completeness, x1 = m[m.length - 1];
    line(ctx, [x0, x1], [c.a - c.b * x0, c.a - c.b * x1], map, "#d62728", 2);
  }
}

function start() {
  const p = DATA.presets[el("preset").value];
  el("stiffness").value = Math.log10(p.stiffness).toFixed(2); el("mass").value = Math.log10(p.mass).toFixed(2);
  slider();
}
for (const id of ["stiffness", "pull", "mass", "damping"]) { el(id).addEventListener("input", slider); }
el("preset").addEventListener("change", start);
el("chain").addEventListener("change", chain);
start(); chain();
"""
