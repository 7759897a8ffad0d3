"""faultslip: laboratory rock-friction stick-slip scaled to earthquake slip and recurrence.

The physics follows seed 003 (Friction-induced oscillations in rock systems):
a spring-slider whose static friction rises as the loading rate falls
(eq. 2-18), whose stick-slip amplitude follows eq. 2-19, and which, scaled to
a strike-slip fault (§5-2), predicts slip per earthquake and recurrence.

Internally every quantity is SI; the year is the Julian year (365.25 d).
"""

from .closed_form import closed_form_cycle, loading_rate, rate_law_amplitude, slip_amplitude
from .errors import FaultslipError, InputError, MethodError, OutOfDomainWarning, SolverError
from .fault import Fault, moment_magnitude, seismic_moment
from .friction import (
    CallableKinetic,
    ConstantKinetic,
    ConstantStatic,
    LinearKinetic,
    PolynomialKinetic,
    RateLaw,
    TimeOfStickLaw,
    static_friction,
)
from .materials import get_lithology, get_preset, lithologies, presets
from .scene import load_scene, run_scene
from .slider import SliderSystem
from .units import JULIAN_YEAR, units

__version__ = "0.1.0"

__all__ = [
    "CallableKinetic", "ConstantKinetic", "ConstantStatic", "Fault", "FaultslipError", "InputError",
    "JULIAN_YEAR", "LinearKinetic", "MethodError", "OutOfDomainWarning", "PolynomialKinetic", "RateLaw",
    "SliderSystem", "SolverError", "TimeOfStickLaw", "closed_form_cycle", "get_lithology", "get_preset",
    "lithologies", "load_scene", "loading_rate", "moment_magnitude", "presets", "rate_law_amplitude",
    "run_scene", "seismic_moment", "slip_amplitude", "static_friction", "units",
]
