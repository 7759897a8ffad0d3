"""faultslip: laboratory rock-friction stick-slip scaled to earthquake slip and recurrence.

The physics follows seed 003 (Friction-induced oscillations in rock systems):
a spring-slider whose static friction rises as the loading rate falls
(eq. 2-18), whose stick-slip amplitude follows eq. 2-19, and which, scaled to
a strike-slip fault (§5-2), predicts slip per earthquake and recurrence.

Internally every quantity is SI; the year is the Julian year (365.25 d).
"""

__version__ = "0.1.0"

# The public API, loaded on first use (PEP 562): "import faultslip" and the command line start fast,
# and a Ctrl-C during start-up reaches the CLI's handler instead of an import.
_EXPORTS = {
    "dynamics.closed_form": ("closed_form_cycle", "loading_rate", "rate_law_amplitude", "slip_amplitude"),
    "errors": ("FaultslipError", "InputError", "MethodError", "OutOfDomainWarning", "SolverError"),
    "fault.scaling": ("Fault", "moment_magnitude", "seismic_moment"),
    "friction.laws": ("CallableKinetic", "ConstantKinetic", "ConstantStatic", "LinearKinetic", "PolynomialKinetic",
                      "RateLaw", "TimeOfStickLaw", "static_friction"),
    "friction.materials": ("get_lithology", "get_preset", "lithologies", "presets"),
    "friction.fitting": ("fit_rate_law", "read_friction_data"),
    "fault.scene": ("load_scene", "run_scene"),
    "dynamics.slider": ("SliderSystem",),
    "dynamics.methods": ("solve",),
    "dynamics.simulate": ("simulate",),
    "dynamics.exact_cycle": ("exact_cycle",),
    "dynamics.critical": ("critical",),
    "studies.grid": ("sweep",),
    "units": ("JULIAN_YEAR", "units"),
    "models": ("run", "Result", "family_of", "families"),
}
_WHERE = {name: module for module, names in _EXPORTS.items() for name in names}
__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        import importlib

        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'faultslip' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
