"""Seed 000's rough-surface slider as a model family: friction from real contact on seed 003's engine."""

from __future__ import annotations

from faultslip.dynamics.methods import solve
from faultslip.dynamics.spring_slider.simulate import simulate as integrate
from faultslip.dynamics.spring_slider.simulate import summary_report
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.dynamics.kernel import REGIME_CODES
from faultslip.dynamics.methods import METHODS, check_lent_method, describe_integrators
from faultslip.errors import InputError
from faultslip.models.rough_surface.scene import read_rough_scene
from faultslip.models.rough_surface import cost as rough_surface_cost
from faultslip.contract.registry import Example, Family, register
from faultslip.contract.result import Result
from faultslip.plots.figures import sawtooth_figure


def _details(report, details) -> None:
    report.section("Rough surfaces (seed 000)")
    report.add("static_friction_model", details["static_friction"], label="mu_s = p_s / H")
    report.add("area_fraction_at_rest", details["area_fraction_at_rest"], label="real / nominal area at rest (L / H A_n)")
    report.add("compression_at_rest", details["compression_at_rest"], "m", label="static compression h0 (H A(h0) = L)")
    reference = "RMS" if details["separation_reference"] == "rms" else "h0"
    report.add("separation_per_speed", details["separation_per_speed"], "s",
               label=f"separation per sliding speed c {reference} (m per m/s)")
    report.add("separation_memory", details["separation_memory"], label="separation memory (none, held, falling)")
    report.add("natural_frequency", details["natural_frequency"], "Hz", label="sqrt(k/M) / 2 pi")


def run(scene, method=None, tolerance=None) -> Result:
    """The stick-slip cycle of a rough-surface scene, by the cheapest accurate method."""
    check_lent_method(method or "auto", "a rough-surface scene")
    system, details, settings = read_rough_scene(scene)
    solution = solve(system, method=method or "auto", tolerance=tolerance or rough_surface_cost.DEFAULT_TOLERANCE,
                     cycles=settings["cycles"], price=rough_surface_cost.price)
    report = solution.report(f"faultslip rough-surface slider (seed 000): {system.name}")
    _details(report, details)
    return Result("rough_surface", report, tolerance=tolerance or rough_surface_cost.DEFAULT_TOLERANCE)


def simulate(scene, cycles=None, slip_solver=None, rtol=None) -> Result:
    """The event-driven simulation of the scene's stick-slip, DOP853 unless ``slip_solver`` says otherwise."""
    system, details, settings = read_rough_scene(scene)
    cycles = cycles or settings["cycles"]
    if not 1 <= cycles <= 10_000:
        raise InputError(f"--cycles must be from 1 to 10000, got {cycles}")
    dataset = integrate(system, cycles=cycles, slip_solver=slip_solver or "DOP853", rtol=rtol or 1e-8, scene=system.name)
    report = summary_report(dataset, f"faultslip simulation (seed 000 rough surfaces): {system.name}")
    _details(report, details)
    return Result("rough_surface", report, dataset, lambda: sawtooth_figure(dataset))


#: What a rough-surface study sweeps ([slider] and [friction] of seed 000's scene) and writes.
PARAMETERS = {name: Parameter(name, kind, unit, long_name, (table, name)) for name, table, kind, unit, long_name in (
    ("mass", "slider", "mass", "kg", "mass M"),
    ("stiffness", "slider", "stiffness", "N/m", "stiffness k"),
    ("normal_load", "slider", "force", "N", "normal load L"),
    ("platform_speed", "slider", "speed", "m/s", "platform speed V0"),
    ("hardness", "friction", "pressure", "Pa", "hardness H"),
    ("shear_strength", "friction", "pressure", "Pa", "shear strength of the junctions"),
    ("separation_coefficient", "friction", "slowness", "s/m", "separation coefficient c (RMS per m/s)"),
)}
#: the event-driven and averaged methods of seed 003's engine a rough-surface cell may take
_METHODS = tuple(name for name in METHODS if name.startswith("event_driven") or name == "quasi_harmonic_averaging")
OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime of the cycle", flags=tuple(REGIME_CODES)),
    Output("slip_per_event", "m", "slip per event, integral of u dt = V T"),
    Output("period", "s", "cycle period T"),
    Output("static_friction", "1", "static friction mu_s"),
    Output("stress_drop", "N", "force drop"),
    Output("peak_slip_speed", "m/s", "peak sliding speed"),
    Output("loading_rate", "1/s", "loading rate theta_dot"),
    Output("method", "1", "method of this cell", flags=_METHODS),
    Output("estimated_relative_error", "1", "estimated relative error of the method"),
)}
CELLS = PerCell("a rough-surface study", PARAMETERS, OUTPUTS, run, read_rough_scene, methods=("auto", *_METHODS),
                seconds=0.5)

FAMILY = register(Family("rough_surface", "seed 000: a slider on rough surfaces, friction from real contact", run,
                         simulate, simulate_options=("cycles", "slip_solver", "rtol"),
                         why="a rough-surface scene takes --cycles, --slip-solver and --rtol",
                         read_scene=toml_reader("rough_surface", PARAMETERS), cells=CELLS,
                         methods=describe_integrators, estimate=rough_surface_cost.estimate,
                         example=Example('rough_surface_seed000.toml', "study_rough_surface.toml",
                                         {'separation_coefficient': ['0 s/m', '0.8 s/m']}, {'cycles': 2})))
