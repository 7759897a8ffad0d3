"""Seed 003's spring-slider as a model family: lab scenes and fault scenes (seed §5-2), with the seed's
static-friction rate law, Cameron's time-of-stick law or rate-and-state friction on the fault."""

from __future__ import annotations

from faultslip import ranges

from faultslip.dynamics.methods import describe_seed_methods, evaluation_time, slip_stiffness, solve
from faultslip.dynamics.spring_slider.simulate import simulate as integrate
from faultslip.dynamics.spring_slider.simulate import summary_report, uniform_channels
from faultslip.errors import EvaluationBudgetError, InputError
from faultslip.fault.scene import CHOICES, read_slider_scene, run_scene
from faultslip.fault.scaling import Fault
from faultslip.fault.spring_slider_cells import CELLS, read_scene
from faultslip.fault.synthetic import simulated_events
from faultslip.io import budget
from faultslip.io.waveforms import build_stream
from faultslip.models.common import note_origin
from faultslip.contract.registry import Example, Family, load, register
from faultslip.contract.result import Result
from faultslip.plots.animation import animation
from faultslip.plots.figures import sawtooth_figure
from faultslip.units import to_si
from faultslip.models.spring_slider import cost as slider_cost


def run(scene=None, method=None, tolerance=None) -> Result:
    """A fault scene's slip and recurrence (or the inverse for mu_m), a lab scene's limit cycle; a
    :class:`~faultslip.fault.scaling.Fault` gives its estimate, as ``faultslip fault`` does."""
    if isinstance(scene, Fault):
        return Result("spring_slider", scene.estimate(method=method or "auto", tolerance=tolerance).report())
    loaded = read_slider_scene(scene)
    if loaded.rate_state:  # one rate-and-state block: its own family, whatever the shape of its file
        return load(loaded.family).run(loaded, method=method, tolerance=tolerance)
    # the tolerance that chose the method is judged (an inverse for mu_m chooses none)
    chosen = None if loaded.kind == "fault" and loaded.observed_slip is not None else (
        loaded.tolerance if tolerance is None else tolerance)
    return Result("spring_slider", run_scene(loaded, method=method, tolerance=tolerance), tolerance=chosen)


def cycle(scene, loading_rate=None, platform_speed=None, method: str | None = None,
          tolerance: float | None = None) -> Result:
    """The exact stick-slip limit cycle of a lab scene's slider at another loading rate or platform speed
    (``faultslip cycle``).

    Parameters
    ----------
    scene : str, path or Scene
        A seed-law scene.
    loading_rate : str or Quantity, optional
        The loading rate theta_dot = K V / W, with units ("0.5 1/s"); give it or ``platform_speed``.
    platform_speed : str or Quantity, optional
        The platform speed V, with units ("1 mm/s").
    method : str, optional
        One of the seed law's methods (the scene's [method] otherwise).
    tolerance : float, optional
        The relative error allowed (the scene's otherwise).

    Returns
    -------
    Result
        The cycle: slip per event (m), period (s), static friction, the method and its declared error.
    """
    loaded = read_slider_scene(scene)
    system = loaded.slider()
    if (loading_rate is None) == (platform_speed is None):
        raise InputError("give exactly one of --loading-rate or --platform-speed")
    # the bounds a scene's own value is held to (faultslip.ranges): 1 km/s had run minutes past any slider's speed
    if loading_rate is not None:
        system = system.at_loading_rate(ranges.check("loading_rate", to_si(loading_rate, "rate", "loading rate"),
                                                     "--loading-rate"))
        ranges.check("platform_speed", system.platform_speed, "the platform speed --loading-rate asks of this slider")
    else:
        system = system.with_(platform_speed=ranges.check(
            "platform_speed", to_si(platform_speed, "speed", "platform speed"), "--platform-speed"))
    solution = solve(system, method=method or loaded.method, tolerance=tolerance or loaded.tolerance, cycles=200)
    return Result("spring_slider", solution.report(f"faultslip cycle: {loaded.name}"))


def animate(scene, cycles: int = 2, frames: int = 120, slip_share: float = 0.5):
    """The slider's block, spring and platform beside its phase plane and friction, over ``cycles`` limit cycles
    (from the first event: the limit cycle, not the first loading from rest)."""
    loaded = read_slider_scene(scene)
    if loaded.rate_state:
        raise InputError("faultslip animate draws a seed-law slider; a rate-and-state scene's cycles are drawn by "
                         "faultslip simulate SCENE --plot FILE.png")
    dataset = integrate(loaded.slider(), cycles=cycles + 1, scene=loaded.name)
    events = dataset["event_time"].values
    if events.size >= 2:
        dataset = dataset.sel(time=slice(events[0] - 0.25 * (events[1] - events[0]), None))
    movie, figure, compression = animation(dataset, frames=frames, slip_share=slip_share)
    return movie, figure, {"title": loaded.name, "cycles": int(max(events.size - 1, 0)),
                           "compression": (compression, "a stick plays this many times faster than a slip")}


def simulate(scene=None, cycles=None, slip_solver=None, rtol=None, allow_large: bool = False, stream: bool = False,
             events: bool = False, output=None) -> Result:
    """The event-driven simulation of a seed-law scene, or a rate-and-state fault's quasi-dynamic cycles.

    ``stream`` and ``events`` ask for the miniSEED stream and QuakeML events (seed-law scenes; events on a
    fault); ``output`` is where the time series goes, for the disk estimate. The result's ``extras``
    build them: ``extras["stream"](rate, start, most)`` and ``extras["events"](start)``.
    """
    if isinstance(scene, Fault):
        raise InputError("a Fault object carries no simulation settings: simulate its scene (a file, or "
                         "faultslip.models.read_slider_scene), or run(fault) for its estimate")
    loaded = read_slider_scene(scene)
    if loaded.rate_state:
        if stream or events:
            raise InputError("--stream and --events apply to seed-law scenes; a rate-and-state scene's cycles are "
                             "written with -o")
        return load(loaded.family).simulate(loaded, cycles=cycles, slip_solver=slip_solver, rtol=rtol)
    if events and loaded.kind != "fault":
        raise InputError("--events writes earthquakes with Mw from M0: it needs a fault scene")
    settings = loaded.simulation
    if cycles is not None:
        if cycles < 1:
            raise InputError(f"--cycles must be at least 1, got {cycles}")
        settings["cycles"] = cycles
    if slip_solver is not None:
        allowed = CHOICES[("simulation", "slip_solver")]
        if slip_solver not in allowed:
            raise InputError(f"--slip-solver must be one of {', '.join(allowed)}, got {slip_solver!r}")
        settings["slip_solver"] = slip_solver
    if rtol is not None:
        if not 1e-14 <= rtol < 1:
            raise InputError(f"--rtol must lie in [1e-14, 1), got {rtol:g}")
        settings["rtol"] = rtol
    system = loaded.slider()
    integrated, solver = slider_cost.simulation_solver(system, settings)
    budget.check(slider_cost.simulation_estimate(settings.get("cycles", 100), settings.get("samples_per_slip", 64),
                                                 integrated, output, system, solver, settings.get("rtol", 1e-10)),
                 allow_large)
    # the evaluations the time budget affords (as run's event-driven method): past them the run stops and says
    # why, not hours later; --allow-large lifts both
    affordable = None if allow_large or not integrated else int(budget.time_budget() / evaluation_time(solver))
    try:
        dataset = integrate(system, scene=loaded.name, max_evaluations=affordable, **settings)
    except EvaluationBudgetError as error:
        raise EvaluationBudgetError(
            f"simulate ({solver}) would pass the time budget ({affordable:.3g} evaluations): {error}; the slip "
            f"phase's stiffness is eps = {slip_stiffness(system):.3g}: an implicit solver (--slip-solver LSODA or "
            "Radau) steps a stiff phase in far fewer evaluations, and --allow-large lifts the budget") from None
    dataset.attrs["scene_text"] = loaded.text
    report = summary_report(dataset, f"faultslip simulation: {loaded.name}")
    note_origin(report, loaded.origin)

    def make_stream(rate, start, most):
        sampling, channels, note = uniform_channels(dataset, rate, most)
        return build_stream(sampling, channels, start_seconds=start), sampling, note

    def make_events(start):
        return simulated_events(dataset, loaded.fault(), loaded.trace, start)

    return Result("spring_slider", report, dataset, lambda: sawtooth_figure(dataset),
                  extras={"stream": make_stream, **({"events": make_events} if loaded.kind == "fault" else {})})


FAMILY = register(Family("spring_slider", "seed 003: the spring-slider, in the lab and scaled to a fault (the "
                         "default)", run, simulate, simulate_options=("cycles", "slip_solver", "rtol", "stream",
                                                                     "events", "output", "allow_large"),
                         read_scene=read_scene, cells=CELLS, methods=describe_seed_methods, animate=animate, estimate=slider_cost.estimate,
                         example=Example('lab_glass_dry.toml', "study_spring_slider.toml",
                                         {'damping_ratio': [0.0, 0.1]}, {'cycles': 2})))
