"""The asperity family's cost model: its integrators' CPU time in simulated seconds, per method, fitted on seed
004's scene by ``benchmarks/family_costs.py`` (the coefficients are in ``data/family_costs.json``)."""

from __future__ import annotations

from faultslip.io import budget
from faultslip.models.asperity.dynamics import CONVERGENCE_RTOLS, MEASURE_PERIODS, choose_method
from faultslip.models.asperity.scene import load_asperity_scene


#: What each run's method imports (budget.Estimate.imports); a simulation also builds a Dataset.
IMPORTS = {"run:asperity_wavelength": (),
           # the slid wavelength is measured from the run's spectrum and its peaks
           "run:asperity_measured_wavelength": (*budget.INTEGRATION_IMPORTS, "scipy.stats", "scipy.signal"),
           "run:asperity_quasistatic": budget.INTEGRATION_IMPORTS, "run:asperity_LSODA": budget.INTEGRATION_IMPORTS}


def work(scene, action: str = "run", method=None, tolerance=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): the run integrates the scene's duration at each tolerance of its convergence
    check (at most :data:`CONVERGENCE_RTOLS`), a simulation once; the closed form costs its overhead alone."""
    model, settings, _notes = load_asperity_scene(scene)
    outputs = ("response",) if action == "run" else ("response", "time_series")
    choice = choose_method(model, outputs, tolerance or settings["tolerance"], method or settings["method"])
    if choice.method == "asperity_wavelength":
        return f"{action}:asperity_wavelength", 0.0, "the critical speeds in closed form"
    if choice.method == "asperity_measured_wavelength":  # MEASURE_PERIODS natural periods at v_c1, at two rtols
        periods = MEASURE_PERIODS / model.natural_frequency
        return (f"{action}:asperity_measured_wavelength", 2 * periods,
                f"two runs (rtol {CONVERGENCE_RTOLS[0]:g}, {CONVERGENCE_RTOLS[1]:g}) of {periods:.3g} s at v_c1 for the "
                "wavelength they slide")
    runs = len(CONVERGENCE_RTOLS) if action == "run" else 1
    duration = settings["duration"]
    return (f"{action}:{choice.method}", duration * runs,
            f"{choice.method} over {duration:g} s of the slider" + (f", at up to {runs} tolerances" if runs > 1 else ""))


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of an asperity scene needs, before it starts."""
    entry, units, what = work(scene, action, **options)
    return budget.fitted_estimate("asperity", entry, units, what, output=options.get("output"),
                                  imports=IMPORTS.get(entry, (*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS)))
