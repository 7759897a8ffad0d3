"""Units at the Python API's boundary: the public functions take "13 mi" and pint Quantities as the command line
does (``faultslip.units.takes_units``), give the SI call's answer, and refuse a wrong unit in one sentence.

Expected values are the same functions called with SI numbers, converted by hand here (1 mi = 1609.344 m,
1 in = 0.0254 m, 1 bar = 1e5 Pa, 1 lbf = 4.4482216152605 N, the Julian year 365.25 d)."""

import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

from faultslip import hazard, lab, models
from faultslip.errors import InputError
from faultslip.friction import static_friction
from faultslip.units import JULIAN_YEAR, takes_units, units

MILE, INCH, BAR, POUND_FORCE = 1609.344, 0.0254, 1e5, 4.4482216152605

magnitudes = st.floats(min_value=1e-3, max_value=1e3)


@given(modulus=magnitudes, length=magnitudes, depth=magnitudes, slip=magnitudes)
def test_the_seismic_moment_of_text_is_the_si_moment(modulus, length, depth, slip):
    expected = hazard.seismic_moment(modulus * 1e4 * BAR, length * MILE, depth * 1e3, slip * INCH)
    given_as_text = hazard.seismic_moment(f"{modulus!r}e4 bar", f"{length!r} mi", f"{depth!r} km", f"{slip!r} in")
    assert given_as_text == pytest.approx(expected, rel=1e-12)
    assert hazard.seismic_moment(units.Quantity(modulus * 1e4, "bar"), units.Quantity(length, "mi"),
                                 f"{depth!r} km", units.Quantity(slip, "in")) == pytest.approx(expected, rel=1e-12)


@given(stiffness=magnitudes, speed=magnitudes, load=magnitudes)
def test_the_loading_rate_takes_a_labs_or_a_faults_units(stiffness, speed, load):
    lab_rate = models.loading_rate(stiffness * POUND_FORCE / INCH, speed * INCH, load * POUND_FORCE)
    assert models.loading_rate(f"{stiffness!r} lbf/in", f"{speed!r} in/s", f"{load!r} lbf") == \
        pytest.approx(lab_rate, rel=1e-12)
    fault_rate = models.loading_rate(stiffness * BAR / MILE, speed * INCH / JULIAN_YEAR, load * BAR)
    assert models.loading_rate(f"{stiffness!r} bar/mi", f"{speed!r} in/yr", f"{load!r} bar") == \
        pytest.approx(fault_rate, rel=1e-12)


def test_a_stiffness_per_area_with_a_force_is_refused_in_one_sentence():
    with pytest.raises(InputError, match=r"normal load is a force but stiffness is a stiffness per area .*: "
                       r"give both whole \(N, N/m\) or both per unit area \(Pa, Pa/m\)"):
        models.slip_amplitude("100 N", "1e6 Pa/m", 0.1)
    with pytest.raises(InputError, match="stiffness must be a stiffness .* or a stiffness per area"):
        models.loading_rate("5 s", "1 um/s", "100 N")
    with pytest.raises(InputError, match="platform speed must be a speed"):
        models.loading_rate("1e4 N/m", "1 s", "100 N")
    with pytest.raises(InputError, match="must be finite"):
        models.loading_rate("nan N/m", "1 um/s", "100 N")


def test_bare_numbers_and_arrays_pass_unchanged_as_si():
    stiffness = np.array([1e3, 1e4])
    assert np.array_equal(models.loading_rate(stiffness, 1e-6, 100.0), stiffness * 1e-6 / 100.0)
    assert models.rate_law_amplitude("1e-3 1/s", "100 N", "1e4 N/m", 0.7, 0.6, 1.0, 0.5) == \
        models.rate_law_amplitude(1e-3, 100.0, 1e4, 0.7, 0.6, 1.0, 0.5)
    assert static_friction("1 1/min", 0.7, 0.6, 1.0, 0.5) == static_friction(1 / 60, 0.7, 0.6, 1.0, 0.5)


def test_a_moment_rate_is_read_per_year_whatever_its_unit():
    """The distributions take N m/yr as bare numbers: a rate per second is converted to it."""
    per_year = hazard.youngs_coppersmith_1985(1e17, 7.5)
    for given_rate in ("1e17 N*m/yr", units.Quantity(1e17 / JULIAN_YEAR, "N*m/s"), "1e24 dyn*cm/yr"):
        assert np.allclose(hazard.youngs_coppersmith_1985(given_rate, 7.5).rates, per_year.rates, rtol=1e-12)
    assert hazard.single_bin("1e17 N*m/yr", 7.5).rates == pytest.approx(hazard.single_bin(1e17, 7.5).rates)
    with pytest.raises(InputError, match="moment rate must be a moment rate"):
        hazard.truncated_gutenberg_richter("1e17 N*m", 7.5)


def test_magnitudes_and_renewal_probabilities_take_units():
    assert hazard.moment_magnitude("1e27 dyn*cm") == pytest.approx(hazard.moment_magnitude(1e20))
    expected = hazard.conditional_probability("bpt", 100 * JULIAN_YEAR, 0.5, 50 * JULIAN_YEAR, 30 * JULIAN_YEAR)
    assert hazard.conditional_probability("bpt", "100 yr", 0.5, "50 yr", units.Quantity(30, "yr")) == \
        pytest.approx(expected, rel=1e-12)
    rates = hazard.displacement_hazard_curve([0.5, 1.0], [1e-3], [7.0], [0.5], average_displacements=[1.0])
    assert np.allclose(hazard.displacement_hazard_curve("50 cm", units.Quantity([1e-3], "1/yr"), [7.0], [0.5],
                                                        average_displacements="1 m"), rates[:1])
    with pytest.raises(InputError, match="horizon must be a time"):
        hazard.conditional_probability("bpt", "100 yr", 0.5, "50 yr", "30 km")


def test_the_labs_functions_take_units():
    decay = lab.free_decay(2.0, 3, "600 1/min", "1e4 N/m")
    assert decay.mass == pytest.approx(lab.free_decay(2.0, 3, 10.0, 1e4).mass, rel=1e-12)
    surface = lab.gaussian_surface("1 um", "10 um", size=16)
    assert np.allclose(surface.height, lab.gaussian_surface(1e-6, 1e-5, size=16).height, rtol=1e-12, atol=0)
    times = np.linspace(0.0, 10.0, 6)
    slips = np.array([1.0, 1.2, 0.9, 1.1, 1.0, 1.3])
    quoted = hazard.predictability(units.Quantity(times, "yr"), units.Quantity(slips * 100, "cm"))
    assert quoted.slip_unit == "cm"
    plain = hazard.predictability(times * JULIAN_YEAR, slips)
    assert quoted.aperiodicity == pytest.approx(plain.aperiodicity) and quoted.slip_correlation == pytest.approx(
        plain.slip_correlation)
    assert quoted.to_xarray()["slips"].attrs["units"] == "cm"


def test_a_declaration_must_name_a_kind_and_an_argument():
    with pytest.raises(KeyError):
        takes_units(width="lenght")
    with pytest.raises(TypeError, match="no argument"):
        takes_units(width="length")(lambda length: length)
    with pytest.raises(KeyError):
        takes_units(width=("length|area", "km"))


def test_a_declared_function_keeps_its_name_signature_and_misuse_is_one_sentence():
    assert models.loading_rate.__name__ == "loading_rate"
    assert list(__import__("inspect").signature(models.loading_rate).parameters) == [
        "stiffness", "platform_speed", "normal_load"]
    with pytest.raises(InputError, match=r"loading_rate\(\): .*argument"):
        models.loading_rate("1e4 N/m", "1 um/s", "100 N", "extra")
    assert math.isfinite(models.loading_rate(stiffness="1e4 N/m", platform_speed=1e-6, normal_load="100 N"))


def test_the_model_classes_take_units_and_a_sliders_scale_names_its_kind():
    """A class's constructor takes units as a function does (takes_units on the class). A slider's ``scale`` says
    whether its quantities are whole (lab: N, N/m) or per unit area (fault: Pa, Pa/m); a value of the other kind
    is refused in one sentence."""
    import dataclasses

    from faultslip.friction import LinearKinetic, TimeOfStickLaw
    from faultslip.models import AsperityModel, Chain, Fault, QuasiHarmonic, SliderSystem

    assert AsperityModel(platform_speed="3.6 mm/s").platform_speed == pytest.approx(
        AsperityModel(platform_speed=3.6e-3).platform_speed, rel=1e-12)
    averaged = QuasiHarmonic(mass="1 kg", damping="1 N*s/m", stiffness="1e4 N/m", normal_load="10 lbf",
                             speed="1 mm/s", coefficients=(0.5,))
    assert averaged.normal_load == pytest.approx(10 * POUND_FORCE, rel=1e-12)
    assert LinearKinetic(0.5, "1 s/cm").slope == pytest.approx(100.0) and TimeOfStickLaw(0.5, 0.6, "2 1/min") == \
        TimeOfStickLaw(0.5, 0.6, 2 / 60)
    chain = Chain(mass="1 kg", leaf_stiffness="1 N/cm", coupling_stiffness=1.0, normal_load="1 N",
                  platform_speed="1 cm/s", static_friction=np.array([0.6]), kinetic_friction=0.5)
    assert chain.leaf_stiffness == pytest.approx(100.0) and chain.platform_speed == pytest.approx(0.01)
    lab = SliderSystem.from_preset("glass_dry", platform_speed="1 um/s")
    assert dataclasses.replace(lab, stiffness="2e4 N/m").stiffness == 2e4
    with pytest.raises(InputError, match="scale = 'lab' does not take: give it in N/m"):
        dataclasses.replace(lab, stiffness="1e6 Pa/m")
    fault = SliderSystem.from_fault(Fault(slip_rate="2 in/yr", zone_width="13 mi", lithology="granodiorite_water",
                                          shear_stress="250 bar"))
    assert dataclasses.replace(fault, stiffness="1 bar/mi").stiffness == pytest.approx(BAR / MILE, rel=1e-12)
    with pytest.raises(InputError, match="scale = 'fault' does not take: give it in Pa"):
        dataclasses.replace(fault, normal_load="100 N")
    with pytest.raises(InputError, match="leaf stiffness must be a stiffness"):
        Chain(mass=1.0, leaf_stiffness="1 N", coupling_stiffness=1.0, normal_load=1.0, platform_speed=1.0,
              static_friction=np.array([0.6]), kinetic_friction=0.5)


def _decorated():
    """Every public callable that takes units: (its qualified name, the callable, its declarations)."""
    import importlib
    import pkgutil

    import faultslip

    found = {}
    for module in pkgutil.walk_packages(faultslip.__path__, "faultslip."):
        if module.name.endswith("__main__") or ".apps" in module.name or ".cli" in module.name:
            continue
        for name, value in vars(importlib.import_module(module.name)).items():
            declared = getattr(value, "__units__", None)
            if isinstance(declared, dict) and getattr(value, "__module__", None) == module.name:
                found[f"{module.name}.{name}"] = (value, declared)
    return found


def test_a_unit_string_outside_its_arguments_physical_range_is_refused_before_the_function_runs():
    """A converted value is checked against its argument's range (faultslip.ranges, by name) in the wrapper, before
    the function's body: "-10 km" for a rupture length used to give a negative moment. Every declared argument
    with a rule, in every public callable, refuses a negative value in one sentence naming the function and the
    argument, whatever the other arguments are (1.0 each, never reached)."""
    import inspect

    from faultslip import ranges
    from faultslip.units import KINDS

    checked = 0
    for qualified, (target, declared) in _decorated().items():
        function = target.__init__ if inspect.isclass(target) else target
        parameters = [p for name, p in inspect.signature(function).parameters.items() if name != "self"]
        for argument, spec in declared.items():
            rule = ranges.ALIASES.get(argument, argument)
            if rule not in ranges.RULES or ranges.RULES[rule][0] not in (ranges.POSITIVE, ranges.NON_NEGATIVE):
                continue
            kind, unit = (spec, None) if isinstance(spec, str) else spec
            text = f"-1 {unit or KINDS[kind.split('|')[0]][1] or 'dimensionless'}"
            call = {p.name: 1.0 for p in parameters if p.default is inspect.Parameter.empty
                    and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)}
            call[argument] = text
            with pytest.raises(InputError, match=rf"{target.__name__}\(\) argument {argument}\)"):
                target(**call)
            checked += 1
    assert checked >= 30
    with pytest.raises(InputError, match=r"rupture length must be positive, got -10000 m \(seismic_moment\(\)"):
        hazard.seismic_moment("30 GPa", "-10 km", "12 km", "2 m")
    with pytest.raises(InputError, match="normal load must be positive, got 0 N"):
        models.loading_rate("1e6 N/m", "1 mm/s", "0 N")
    # bounds in the rule's unit only: a fault's stiffness in Pa/m is checked for its sign, not the lab's N/m bounds
    assert models.loading_rate("1e-9 Pa/m", "1 mm/yr", "1 MPa") > 0
    with pytest.raises(InputError, match="stiffness must lie between"):
        models.loading_rate("1e-9 N/m", "1 mm/s", "1 N")


def test_a_plain_number_is_checked_for_its_sign_and_a_functions_own_domain_replaces_the_scenes():
    """Plain numbers had passed unchecked: seismic_moment(3e10, -1e4, 1.2e4, 2.0) returned -7.2e18 N m. Every
    declared argument with a sign rule now refuses a plain -1.0 as it refuses "-1 <unit>", in one sentence naming
    the function and the argument; arrays (the vectorised callers') and NaN pass as given. A function defined
    beyond the scene's range keeps its domain: the static friction at a loading rate of 0 is the rate law's mu_so
    (seed 003 eq. 2-18), as number and as text."""
    import inspect

    import numpy as np

    from faultslip import ranges
    from faultslip.friction.laws import static_friction

    with pytest.raises(InputError, match=r"rupture length must be positive, got -10000 m \(seismic_moment\(\)"):
        hazard.seismic_moment(3e10, -1e4, 1.2e4, 2.0)
    with pytest.raises(InputError, match=r"seismic moment must be positive, got -1e\+18"):
        hazard.moment_magnitude(-1e18)
    assert hazard.seismic_moment(3e10, 1e4, 1.2e4, 2.0) == pytest.approx(7.2e18)  # in range: unchanged, SI
    assert hazard.seismic_moment(3e10, 1e3 * 10.0 ** 6, 1.2e4, 2.0) > 0  # beyond the text's bounds: a sign only
    lengths = np.array([-1e4, 1e4])
    assert hazard.seismic_moment(3e10, lengths, 1.2e4, 2.0)[0] < 0  # an array is the caller's
    assert np.isnan(hazard.seismic_moment(3e10, 1e4, 1.2e4, np.nan))
    granodiorite = dict(mu_so=0.65, mu_m=0.5, b=1.0, d=0.5)
    assert static_friction(0.0, **granodiorite) == static_friction("0 1/s", **granodiorite) == pytest.approx(0.65)
    with pytest.raises(InputError, match=r"loading rate must not be negative.*static_friction\(\) argument"):
        static_friction(-1.0, **granodiorite)
    checked = 0
    for qualified, (target, declared) in _decorated().items():
        function = target.__init__ if inspect.isclass(target) else target
        parameters = [p for name, p in inspect.signature(function).parameters.items() if name != "self"]
        for argument in declared:
            rule = ranges.ALIASES.get(argument, argument)
            if rule not in ranges.RULES or ranges.RULES[rule][0] not in (ranges.POSITIVE, ranges.NON_NEGATIVE):
                continue
            call = {p.name: 1.0 for p in parameters if p.default is inspect.Parameter.empty
                    and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)}
            call[argument] = -1.0
            with pytest.raises(InputError, match=rf"{target.__name__}\(\) argument {argument}\)"):
                target(**call)
            checked += 1
    assert checked >= 30
