"""A chain of spring-blocks as a model family: a fault of many blocks whose catalogue has sizes.

One slider repeats one earthquake. A chain of them (Burridge & Knopoff 1967; Carlson & Langer 1989),
coupled to their neighbours and loaded through leaf springs, slips in events of one block to all of
them: a catalogue with a magnitude-frequency distribution, a b-value and scatter in recurrence.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.contract.cells import PerCell
from faultslip.models.spring_chain import cost as spring_chain_cost
from faultslip.contract.registry import Example, Family, register
from faultslip.contract.result import Result
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.errors import InputError
from faultslip.io import budget
from faultslip.fault.gutenberg_richter import b_value, gr_test
from faultslip.fault.scaling import moment_magnitude
from faultslip.intervals import correlated_mean_half_width
from faultslip.io.report import Report
from faultslip.io.waveforms import DEFAULT_START
from faultslip.models.common import note_origin
from faultslip.models.spring_chain.dynamics import (INTEGRATORS, SAMPLES_PER_PERIOD, SLIP_SOLVERS, ChainRun,
                                                    chosen_solver, simulate_chain)
from faultslip.models.spring_chain.figures import chain_animation, chain_figure
from faultslip.models.spring_chain.scene import read_chain_scene

METHOD = {"name": "chain_event_driven_exact",
          "friction_laws": "the seed's rate-law static friction (a threshold for each block) or constant static; "
                           "constant kinetic friction",
          "domain": "1 to 2000 blocks; damping below critical (c < 2 sqrt(k_p m)); blocks slip either way",
          "cost_model": "O(sub-phases x n^2) with n the blocks slipping, 2 or more sub-phases a block an event: "
                        "about 4 us a sub-phase compiled (closed_form_compiled, auto's choice where it was built), "
                        "0.4 ms in Python (closed_form); 100 blocks, 10,000 events in 1.5 s compiled "
                        "(benchmarks/spring_chain_speed.py)",
          "declared_error": "the catalogue's: the mean system-size interval's 95 % half-width (Student's t with the "
                            "intervals' autocorrelation time and a factor set on random chains; none below 10 "
                            "intervals; more events narrow it, and a tolerance asks for them); each event's own is "
                            "the closed form's round-off: each sub-phase's end is bracketed on "
                            f"{SAMPLES_PER_PERIOD} points a period of its fastest mode and located by Brent's method "
                            "to 1e-13 of the step (one block agrees with the exact cycle to 1e-10)"}
INTEGRATED = {"name": "chain_event_driven_integrated",
              "friction_laws": METHOD["friction_laws"],
              "domain": METHOD["domain"] + "; slip_solver = " + ", ".join(INTEGRATORS),
              "cost_model": "scipy's solve_ivp with a terminal event a slipping block and a held neighbour: about 2.7 "
                            "times the Python closed form's time at 100 blocks (benchmarks/spring_chain_speed.py)",
              "declared_error": "the integrator's rtol (default 1e-10) on each sub-phase's end; a chaotic chain's "
                                "catalogue departs from the closed form's after tens of events, its statistics do not",
              "run_method": None,
              "selected_by": (f"a check on the closed form, not a run method: 'faultslip simulate SCENE --slip-solver "
                              f"{INTEGRATORS[0]}' (or {', '.join(INTEGRATORS[1:])}) integrates the chain's slip phases "
                              "with it")}


def _moments(loaded, run: ChainRun) -> tuple[np.ndarray, np.ndarray]:
    """Each event's moment G A sum(slip) (N m) and Mw; an event whose slips cancel has no magnitude (NaN)."""
    moment = loaded.shear_modulus * loaded.patch_area * run.total_slip
    with np.errstate(divide="ignore", invalid="ignore"):
        return moment, np.where(moment > 0, moment_magnitude(np.maximum(moment, 1e-300)), np.nan)


def _catalogue(loaded, run: ChainRun):
    """The catalogue as an xarray Dataset with CF units: one row per event, the slip of every block."""
    import xarray as xr  # heavy: imported where used

    moment, magnitude = _moments(loaded, run)
    event = np.arange(run.events)
    # the time series: every block's position at the start and after each event (a staircase per block)
    position = np.cumsum(np.vstack([np.zeros(run.chain.blocks), run.slip]), axis=0) + (
        run.final_position - run.slip.sum(axis=0))
    data = {
        "position": (("time", "block"), position, {"units": "m", "long_name": "block position (after each event)"}),
        "event_start": ("event", run.start, {"units": "s", "long_name": "event start (model time)"}),
        "event_end": ("event", run.end, {"units": "s", "long_name": "time the last block stopped"}),
        "blocks_slipped": ("event", run.blocks_slipped.astype(float), {"units": "1", "long_name": "blocks that slipped"}),
        "first_block": ("event", run.first_block.astype(float), {"units": "1", "long_name": "block that failed first"}),
        "slip": (("event", "block"), run.slip, {"units": "m", "long_name": "slip of each block in the event"}),
        "total_slip": ("event", run.total_slip, {"units": "m", "long_name": "slip summed over the blocks"}),
        "moment": ("event", moment, {"units": "N m", "long_name": "seismic moment G A sum(slip)"}),
        "magnitude": ("event", magnitude, {"units": "1", "long_name": "moment magnitude (2/3)(log10 M0 - 9.1)"}),
        "peak_slip_speed": ("event", run.peak_speed, {"units": "m/s", "long_name": "fastest block speed"}),
        "static_friction": ("block", run.chain.static_friction, {"units": "1", "long_name": "static limit mu_s of each block"}),
    }
    coords = {"event": ("event", event, {"units": "1", "long_name": "event number"}),
              "time": ("time", np.concatenate([[0.0], run.end]), {"units": "s", "long_name": "model time: the start, "
                                                                  "then the end of each event"}),
              "block": ("block", np.arange(run.chain.blocks), {"units": "1", "long_name": "block number"})}
    return xr.Dataset(data, coords=coords, attrs={
        "title": f"faultslip spring-block chain: {loaded.name}", "Conventions": "CF-1.8",
        "blocks": run.chain.blocks, "leaf_stiffness_N_per_m": run.chain.leaf_stiffness,
        "coupling_stiffness_N_per_m": run.chain.coupling_stiffness, "kinetic_friction": run.chain.kinetic_friction,
        "platform_speed_m_per_s": run.chain.platform_speed, "normal_load_N": run.chain.normal_load,
        "damping_ratio": run.chain.damping_ratio, "shear_modulus_Pa": loaded.shear_modulus,
        "patch_area_m2": loaded.patch_area, "friction": loaded.friction})


def statistics(loaded, run: ChainRun) -> dict:
    """What a chain's catalogue says: b-value, system-size recurrence and its scatter, the plate's balance.

    Parameters
    ----------
    loaded : ChainScene
        The scene (its moment per slip and its start).
    run : ChainRun
        Its run.

    Returns
    -------
    dict
        ``gr`` (:func:`faultslip.fault.gutenberg_richter.gr_test`, or None), ``b`` (its b-value above the test's
        M_c where Gutenberg-Richter holds, else None with ``b_reason``), ``magnitude_range``,
        ``system_events``, ``recurrence`` (s), ``recurrence_cv``, ``plate_balance`` (min, max of each block's slip /
        (V t)) with ``plate_balance_bound`` and the per-block arrays, and ``magnitude``.
    """
    _, magnitude = _moments(loaded, run)
    sized = magnitude[np.isfinite(magnitude)]
    stats = {"magnitude_range": (float(sized.min()), float(sized.max())) if sized.size else (math.nan, math.nan)}
    try:  # a b-value only where the catalogue follows Gutenberg-Richter above its cutoff (gr_test)
        stats["gr"] = gr_test(sized)
        if stats["gr"]["holds"]:
            stats["b"] = b_value(sized, completeness=stats["gr"]["completeness"])
        else:
            gr = stats["gr"]
            stats["b"] = None
            stats["b_reason"] = (f"the catalogue is not Gutenberg-Richter (Kolmogorov-Smirnov p = {gr['p_value']:.2g} "
                                 f"above M_c = {gr['completeness']:.3g}, and b moves from {gr['b_range'][0]:.2f} to "
                                 f"{gr['b_range'][1]:.2f} with the cutoff): read its magnitude-frequency distribution")
    except InputError as exc:  # too few events, or every event the same size (identical blocks): no b-value
        stats["gr"], stats["b"] = None, None
        stats["b_reason"] = str(exc)
    chain = run.chain
    starts = system_event_times(run, loaded.system_size)
    intervals = np.diff(starts)
    stats["system_events"] = int(starts.size)
    stats["recurrence"] = float(intervals.mean()) if intervals.size else math.nan
    stats["recurrence_cv"] = float(intervals.std(ddof=1) / intervals.mean()) if intervals.size > 1 else math.nan
    stats["recurrence_half_width"] = recurrence_half_width(intervals)
    # the plate's balance: each block's slip x_i(T) - x_i(0) against the plate's V T. A held block's force
    # k_p (V T - x_i) + c V + k_c sum(x_j - x_i) lies within +-W mu_s,i, which bounds V T - x_i(T): the
    # ratio tends to 1 as 1 / T, inside a bound computed here for each block
    elapsed = run.final_time
    ratio = run.slip.sum(axis=0) / (chain.platform_speed * elapsed)
    final = run.final_position
    neighbours = np.zeros(chain.blocks)
    if chain.blocks > 1:
        gaps = np.abs(np.diff(final))
        neighbours[:-1] += gaps
        neighbours[1:] += gaps
    stored = (chain.normal_load * chain.static_friction + chain.dashpot * chain.platform_speed
              + chain.coupling_stiffness * neighbours) / chain.leaf_stiffness
    bound = (stored + np.abs(loaded.initial_position)) / (chain.platform_speed * elapsed)
    stats["plate_balance"] = (float(ratio.min()), float(ratio.max()))
    stats["plate_balance_each"] = ratio
    stats["plate_balance_bound_each"] = bound
    stats["plate_balance_bound"] = float(bound.max())
    stats["magnitude"] = magnitude
    stats["system_fraction"] = loaded.system_size
    return stats


def system_event_times(run: ChainRun, system_size: float) -> np.ndarray:
    """The start times (s) of the run's system-size events: those slipping ``system_size`` of the blocks or more."""
    return run.start[run.blocks_slipped >= system_size * run.chain.blocks]


#: Fewest system-size intervals a range is declared on: fewer cannot show their own correlation, and a short run's
#: first events still carry the chain's uniform start (benchmarks/chain_coverage.py).
MIN_SYSTEM_INTERVALS = 10
#: The factor on the correlated half-width that makes 95 % of calibration chains' ranges hold their long-run mean
#: (benchmarks/chain_coverage.py, results/chain_coverage.json; a test checks that the fit gives this value).
RANGE_FACTOR = 1.7


def recurrence_half_width(intervals, factor: float = RANGE_FACTOR) -> float:
    """The 95 % half-width of the mean interval between system-size events, relative to it (NaN below
    :data:`MIN_SYSTEM_INTERVALS`): ``factor`` t_{0.975, n - 1} s sqrt(tau) / (sqrt(n) mean) over the n intervals
    (:func:`faultslip.intervals.correlated_mean_half_width`). tau, their integrated autocorrelation time, counts
    the serial correlation a short run shows; ``factor`` (:data:`RANGE_FACTOR`) covers what it cannot show: the
    correlation beyond its window, a mean skewed by a few long intervals, and the first events' memory of the
    uniform start. It was set on random chains so that the range holds a thirty times longer run's mean on 95 %
    of them, and checked on others."""
    intervals = np.asarray(intervals, dtype=float)
    if intervals.size < MIN_SYSTEM_INTERVALS:
        return math.nan
    return correlated_mean_half_width(intervals, 0.95, factor)


def _report(loaded, run: ChainRun, stats: dict, title: str, method: str = METHOD["name"],
            numerical: float = 1e-10) -> Report:
    chain = run.chain
    report = Report(title)
    report.add("method", method)
    report.add("blocks", chain.blocks).add("events", run.events)
    report.add("friction", loaded.friction)
    report.add("coupling_ratio", chain.coupling_stiffness / chain.leaf_stiffness, label="k_c / k_p")
    report.add("damping_ratio", chain.damping_ratio, label="c / (2 sqrt(k_p m))")
    low, high = stats["magnitude_range"]
    report.add("magnitude_min", low).add("magnitude_max", high)
    if stats["b"] is not None:
        b = stats["b"]
        report.add("b_value", b["b"], label=f"Aki's maximum likelihood above M_c = {b['completeness']:.3g} "
                                              f"({b['count']} events)")
        report.add("b_value_interval", list(b["interval"]), "1", label="95 % interval (chi-square, exact)")
        report.add("b_value_error", b["shi_bolt_error"], label="Shi & Bolt's standard error")
    else:
        report.add("b_value", None, label="no b-value: " + stats["b_reason"])
    gr = stats.get("gr")
    if gr is not None:
        report.add("gutenberg_richter", gr["holds"], label="the magnitudes follow Gutenberg-Richter above M_c")
        report.add("gutenberg_richter_p_value", gr["p_value"], label="Kolmogorov-Smirnov p-value of the fitted law")
        report.add("b_value_over_cutoffs", list(gr["b_range"]), label="b at every candidate cutoff (how much the "
                                                                       "choice of M_c alone moves it)")
        report.note(gr["method"])
    report.add("system_size_events", stats["system_events"],
               label=f"events slipping {loaded.system_size:.0%} of the blocks or more")
    report.add("recurrence_interval", stats["recurrence"] if math.isfinite(stats["recurrence"]) else None, "s",
               also=("yr",), label="mean interval between system-size events")
    report.add("recurrence_cv", stats["recurrence_cv"] if math.isfinite(stats["recurrence_cv"]) else None,
               label="coefficient of variation of those intervals (0 periodic, 1 Poisson)")
    half = stats["recurrence_half_width"]
    if math.isfinite(half):
        mean = stats["recurrence"]
        report.add("recurrence_interval_range", [mean * (1 - half), mean * (1 + half)], "s", also=("yr",),
                   label=f"95 % range of the mean interval (Student's t over the system-size intervals, their "
                         f"autocorrelation time and a factor {RANGE_FACTOR:g} set on random chains)")
    # the answer is a statistic of the catalogue: its sampling error, not the closed form's round-off, bounds it
    report.add("estimated_relative_error", half if math.isfinite(half) else None,
               label=f"declared error: the mean interval's 95 % half-width over {max(stats['system_events'] - 1, 0)} "
                     f"system-size intervals (null: fewer than {MIN_SYSTEM_INTERVALS}; more events narrow it)")
    report.add("numerical_error", numerical, label="each event's own error (the closed form's round-off, or the "
                                                   "integrator's rtol)")
    report.add("mean_slip_per_event", float(run.total_slip.mean() / chain.blocks), "m",
               label="slip per event, averaged over the blocks")
    report.add("plate_slip_balance_range", list(stats["plate_balance"]), "1",
               label="each block's slip / (V t) (min, max)")
    report.add("plate_slip_balance_bound", stats["plate_balance_bound"],
               label="how far from 1 the stretch still stored allows")
    report.add("subphases", run.subphases).add("wall_time", run.wall_time, "s")
    report.add("duration", run.final_time, "s", also=("yr",))
    note_origin(report, getattr(loaded, "origin", ""))
    return report


def _run(scene, events=None, title="faultslip spring-block chain", slip_solver=None, rtol=None):
    loaded = read_chain_scene(scene)
    count = loaded.events if events is None else events
    if not (isinstance(count, (int, np.integer)) and not isinstance(count, bool) and 1 <= count <= 1_000_000):
        raise InputError(f"--cycles (the chain's events) must be a whole number from 1 to 1,000,000, got {count!r}")
    solver = chosen_solver("auto" if slip_solver in (None, "analytic") else slip_solver)
    if solver not in SLIP_SOLVERS:
        raise InputError(f"--slip-solver for a spring-block chain must be auto, analytic (the closed form) or one of "
                         f"{', '.join(SLIP_SOLVERS[1:])}, got {slip_solver!r}")
    run = simulate_chain(loaded.chain, int(count), initial_position=loaded.initial_position, slip_solver=solver,
                         rtol=1e-10 if rtol is None else rtol)
    stats = statistics(loaded, run)
    report = _report(loaded, run, stats, f"{title}: {loaded.name}",
                     INTEGRATED["name"] if solver in INTEGRATORS else METHOD["name"],
                     (1e-10 if rtol is None else rtol) if solver in INTEGRATORS else 1e-10)
    report.add("slip_solver", {"closed_form": "analytic (closed form, in Python)",
                               "closed_form_compiled": "analytic (closed form, compiled)"}.get(solver, solver))
    return loaded, run, stats, report


#: The most events a run takes to meet a tolerance (the scene's own run is the least): about 8 s at 12 blocks, a
#: half-width near 0.5 % where the intervals scatter by half their mean.
MOST_EVENTS = 100_000


def check_method(method) -> None:
    """Refuse a method other than the chain's one (or auto), in one sentence (run and estimate alike)."""
    if method not in (None, "auto", METHOD["name"]):
        raise InputError(f"a spring-block chain has one method, {METHOD['name']} (or auto), not {method!r}")


def estimate(scene, action: str = "run", **options):
    """What a run or simulation of a chain scene needs, before it starts (cost.py); a run's method that run
    refuses, refused here too."""
    if action == "run":
        check_method(options.get("method"))
    return spring_chain_cost.estimate(scene, action, **options)


def run(scene, method=None, tolerance=None, allow_large: bool = False) -> Result:
    """The chain's catalogue and what it says: b-value, system-size recurrence, the plate's balance.

    Its declared error is the mean interval's 95 % sampling half-width (:func:`recurrence_half_width`). Where a
    ``tolerance`` is given and the scene's events do not meet it, the run is made again with the events the
    half-width's 1 / sqrt(n) says it needs (estimated and budgeted first; at most :data:`MOST_EVENTS`)."""
    check_method(method)
    budget.check(spring_chain_cost.estimate(scene, "run"), allow_large)  # the scene's own run, before any work
    loaded, chain_run, stats, report = _run(scene)
    half = stats["recurrence_half_width"]
    if tolerance is not None and not half <= tolerance and loaded.events < MOST_EVENTS:
        events = loaded.events
        # the half-width falls as 1 / sqrt(intervals); with too few to declare one there is nothing to scale: ten times
        grown = events * min(half / tolerance, 1e6) ** 2 * 1.2 if math.isfinite(half) else 10.0 * events
        needed = int(min(MOST_EVENTS, max(2 * events, math.ceil(grown))))
        estimate = spring_chain_cost.estimate(scene, "simulate", cycles=needed)
        estimate.what = f"{needed:,} events of {loaded.name}, for the tolerance {tolerance:g}"
        budget.check(estimate, allow_large)
        loaded, chain_run, stats, report = _run(scene, needed)
        report.add("method_reason", f"{needed:,} events, not the scene's {events:,}: the mean interval's 95 % "
                                    f"half-width over the scene's ({half:.2g}) exceeded the tolerance {tolerance:g}")
    dataset = _catalogue(loaded, chain_run)
    return Result("spring_chain", report, dataset, lambda: chain_figure(dataset, stats), extras={"run": chain_run})


def simulate(scene, cycles=None, slip_solver=None, rtol=None, events=False, output=None) -> Result:
    """The chain's events (``cycles`` of them, the scene's otherwise) with their catalogue; ``slip_solver`` auto
    or analytic (the closed form, compiled where it was built), closed_form (in Python), closed_form_compiled,
    or a scipy integrator at ``rtol``; ``events`` asks for QuakeML
    (``extras["events"](start)``)."""
    loaded, chain_run, stats, report = _run(scene, cycles, "faultslip simulation of a spring-block chain",
                                            slip_solver, rtol)
    dataset = _catalogue(loaded, chain_run)

    def make_events(start=DEFAULT_START):
        magnitude = dataset["magnitude"].values
        sized = np.flatnonzero(np.isfinite(magnitude))  # an event whose slips cancel has no moment to give an Mw
        count = sized.size
        note = "a chain has no geography: its events are placed at 0 N 0 E, 5 km deep"
        if count < magnitude.size:
            note += f"; {magnitude.size - count} events whose slips sum to no forward slip have no Mw and are left out"
        return {"times": start + chain_run.start[sized], "latitude": np.zeros(count), "longitude": np.zeros(count),
                "depth": np.full(count, 5e3), "magnitude": magnitude[sized],
                "names": [f"{loaded.name}: chain event {i + 1} ({int(chain_run.blocks_slipped[i])} blocks)"
                          for i in sized], "note": note}

    return Result("spring_chain", report, dataset, lambda: chain_figure(dataset, stats),
                  extras={"run": chain_run, "events": make_events})


def animate(scene, cycles: int = 2, frames: int = 120, slip_share: float = 0.5):
    """The chain's last ``frames`` events (the scene's events run), one a frame (``cycles`` and ``slip_share``, a
    slider's, do not apply: a chain's frame is an event)."""
    loaded, chain_run, stats, _ = _run(scene)
    gr = stats.get("gr")
    title = (f"{loaded.name}: b = {stats['b']['b']:.2f} (GR test p = {gr['p_value']:.2g})"
             if stats["b"] is not None and gr is not None else loaded.name)
    movie, figure = chain_animation(chain_run, frames, title)
    return movie, figure, {"title": loaded.name, "events": min(frames, chain_run.events),
                           "b_value": stats["b"]["b"] if stats["b"] is not None else None}


#: What a chain study sweeps and writes.
PARAMETERS = {
    **{name: Parameter(name, kind, unit, long_name, ("chain", name)) for name, kind, unit, long_name in (
        ("coupling_stiffness", "stiffness", "N/m", "coupling spring k_c"),
        ("leaf_stiffness", "stiffness", "N/m", "leaf spring k_p"),
        ("platform_speed", "speed", "m/s", "plate speed V"),
        ("normal_load", "force", "N", "normal load W"))},
    **{name: Parameter(name, "dimensionless", "1", long_name, ("chain", name), number=True)
       for name, long_name in (("threshold_spread", "spread of the static limits"),
                               ("damping_ratio", "damping ratio of a block"), ("blocks", "number of blocks"))},
}
OUTPUTS = {spec.name: spec for spec in (
    Output("b_value", "1", "Gutenberg-Richter b-value (Aki's maximum likelihood)"),
    Output("b_value_error", "1", "Shi & Bolt's standard error of the b-value"),
    Output("magnitude_max", "1", "largest moment magnitude"),
    Output("recurrence_interval", "s", "mean interval between system-size events"),
    Output("recurrence_cv", "1", "coefficient of variation of the system-size intervals"),
    Output("mean_slip_per_event", "m", "slip per event averaged over the blocks"),
    Output("estimated_relative_error", "1", "declared error: the mean interval's 95 % sampling half-width"),
)}
CELLS = PerCell("a spring-block chain study", PARAMETERS, OUTPUTS, run, read_chain_scene,
                methods=("auto", METHOD["name"]), seconds=5.0)

FAMILY = register(Family("spring_chain", "a chain of spring-blocks (Burridge & Knopoff): catalogues with sizes", run,
                         simulate, simulate_options=("cycles", "slip_solver", "rtol", "events"),
                         run_options=("allow_large",),
                         why="a spring-block chain takes --cycles (its events), --slip-solver, --rtol and --events "
                             "(QuakeML)",
                         read_scene=toml_reader("spring_chain", PARAMETERS), cells=CELLS,
                         methods=lambda: [dict(METHOD), dict(INTEGRATED)], animate=animate, estimate=estimate,
                         example=Example('spring_chain_small.toml', "study_spring_chain.toml",
                                         {'threshold_spread': [0.3, 0.5]}, {'cycles': 20})))
