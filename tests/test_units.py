"""Units at the boundary: parsing, the Julian year, and rejected inputs."""

import math

import numpy as np
import pint
import pytest

from faultslip.errors import InputError
from faultslip.units import JULIAN_YEAR, STANDARD_GRAVITY, to_si, units


def test_year_is_julian_everywhere():
    assert JULIAN_YEAR == 365.25 * 86400
    assert units.Quantity(1, "year").to("s").magnitude == JULIAN_YEAR
    assert units.Quantity(1, "yr").to("day").magnitude == 365.25
    # seed 003 used 365 d: 0.068 % shorter
    assert math.isclose(JULIAN_YEAR / (365 * 86400) - 1, 0.000685, rel_tol=1e-2)


@pytest.mark.parametrize(
    "text, kind, expected",
    [
        ("13 mi", "length", 13 * 1609.344),
        ("2 in/yr", "speed", 2 * 0.0254 / JULIAN_YEAR),
        ("0.25e6 bar", "pressure", 0.25e11),
        ("250 bar", "pressure", 2.5e7),
        ("24 mm/yr", "speed", 0.024 / JULIAN_YEAR),
        ("1.94e4 lbf/in", "stiffness", 1.94e4 * 4.4482216152605 / 0.0254),
        ("5e-11 1/s", "rate", 5e-11),
        ("2700 kg/m^3", "density", 2700.0),
        ("3.3 km/s", "speed", 3300.0),
    ],
)
def test_examples_from_the_issue_parse_to_si(text, kind, expected):
    assert to_si(text, kind, "x") == pytest.approx(expected, rel=1e-13)


def test_pint_quantity_and_foreign_registry_are_accepted():
    assert to_si(units.Quantity(13, "mi"), "length", "D") == pytest.approx(20921.472)
    other = pint.UnitRegistry()
    assert to_si(other.Quantity(2, "in/yr"), "speed", "V") == pytest.approx(2 * 0.0254 / JULIAN_YEAR)


def test_array_quantities_convert_elementwise():
    out = to_si(units.Quantity(np.array([1.0, 2.0]), "bar"), "pressure", "p")
    np.testing.assert_allclose(out, [1e5, 2e5])


def test_wrong_dimension_names_the_input_and_the_kind():
    with pytest.raises(InputError, match=r"slip rate must be a speed .*got 2 bar"):
        to_si("2 bar", "speed", "slip rate")


def test_bare_number_is_rejected_unless_a_default_unit_is_documented():
    with pytest.raises(InputError, match="elastic-zone width must be a length with units"):
        to_si(13, "length", "elastic-zone width")
    assert to_si(13, "length", "D", default_unit="mi") == pytest.approx(20921.472)
    assert to_si("0.65", "dimensionless", "mu_so") == 0.65


def test_dimensionless_rejects_units():
    with pytest.raises(InputError, match="mu_so must be a dimensionless number"):
        to_si("0.65 bar", "dimensionless", "mu_so")


@pytest.mark.parametrize(
    "bad, kind", [("nan", "dimensionless"), ("nan bar", "pressure"), (float("nan"), "dimensionless"), ("inf m", "length")]
)
def test_nan_and_infinity_are_rejected(bad, kind):
    with pytest.raises(InputError, match="finite"):
        to_si(bad, kind, "value")


def test_unknown_unit_is_a_clear_error():
    with pytest.raises(InputError, match="unknown unit 'furlongz' in '13 furlongz'"):
        to_si("13 furlongz", "length", "D")


def test_load_in_pounds_mass_is_read_as_a_weight():
    assert to_si("225.8 lb", "force", "W") == pytest.approx(225.8 * 0.45359237 * STANDARD_GRAVITY)
    assert to_si("225.8 lb", "force", "W") == pytest.approx(to_si("225.8 lbf", "force", "W"), rel=1e-12)
    with pytest.raises(InputError):
        to_si("2 kg", "length", "D")  # the gravitational reading applies to forces only
