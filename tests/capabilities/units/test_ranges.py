"""The physical range of every named input (faultslip.ranges): each positive quantity a scene takes is bounded, so
that no value a user can type makes the arithmetic overflow or underflow into a division by zero."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, strategies as st

from conftest import assert_clean_error
from faultslip import ranges
from faultslip.errors import InputError

ROOT = Path(__file__).resolve().parents[3]
FAULT_SCENE = (ROOT / "configs" / "san_andreas_1906.toml").read_text(encoding="utf-8")
UNITS = {"shear_modulus": "Pa", "zone_width": "m", "shear_stress": "Pa", "slip_rate": "m/s"}


def test_every_positive_or_finite_quantity_has_bounds():
    """A rule of "positive" alone let 1e300 km through as a zone width (found by the fuzzer: the stiffness G / D
    and the slider's natural frequency underflowed, and run and simulate divided by zero)."""
    unbounded = [name for name, (rule, _, _) in ranges.RULES.items()
                 if rule in (ranges.POSITIVE, ranges.FINITE) and name not in ranges.BOUNDS]
    assert unbounded == []
    for name, (low, high) in ranges.BOUNDS.items():
        assert low < high and np.isfinite([low, high]).all(), name


@given(st.sampled_from(sorted(ranges.BOUNDS)), st.floats(allow_nan=False, allow_infinity=False))
def test_a_value_passes_exactly_when_it_lies_within_its_bounds(name, value):
    low, high = ranges.BOUNDS[name]
    rule = ranges.RULES[name][0]
    allowed = low <= value <= high and not (rule == ranges.POSITIVE and value <= 0)
    if allowed:
        assert ranges.check(name, value) == value
    else:
        with pytest.raises(InputError) as caught:
            ranges.check(name, value, "here")
        assert "\n" not in str(caught.value) and "(here)" in str(caught.value)


def test_a_zone_width_of_1e300_km_is_refused_in_one_sentence(cli, tmp_path):
    scene = tmp_path / "wide.toml"
    scene.write_text(FAULT_SCENE.replace('zone_width = "13 mi"', 'zone_width = "1e300 km"'), encoding="utf-8")
    for command in ("run", "simulate", "critical"):
        assert_clean_error(cli(command, scene), "elastic-zone width must lie between", "wide.toml")
    assert_clean_error(cli("fault", "--lithology", "granodiorite_water", "--zone-width", "1e300 km", "--shear-stress",
                           "250 bar", "--slip-rate", "2 in/yr"), "elastic-zone width")


@pytest.mark.parametrize("corner", list(itertools.product(*[ranges.BOUNDS[k] for k in UNITS])))
def test_the_fault_scene_at_every_corner_of_its_bounds_answers_or_refuses_in_one_sentence(cli, tmp_path, corner):
    """The 1906 scene with its modulus, width, stress and slip rate each at a bound, together: the extremes a
    user can type give an answer or one sentence, never a traceback."""
    text = FAULT_SCENE
    for key, value in zip(UNITS, corner):
        text = re.sub(rf"^{key} = .*$", f'{key} = "{value!r} {UNITS[key]}"', text, flags=re.M)
    scene = tmp_path / "corner.toml"
    scene.write_text(text, encoding="utf-8")
    for command in (("run",), ("simulate", "--cycles", "2")):
        result = cli(command[0], scene, *command[1:])
        if result.code != 0:
            assert_clean_error(result)


@pytest.mark.parametrize("given, expected", [(0.1, 0.1), ("0.1", 0.1), ("1e-3", 1e-3), ("10 %", 0.1), ("10%", 0.1),
                                             (" 2.5 % ", 0.025), (1e-12, 1e-12), (None, None)])
def test_a_tolerance_is_read_from_a_number_or_text(given, expected):
    assert ranges.check_tolerance(given) == pytest.approx(expected) if expected else \
        ranges.check_tolerance(given) is None


def test_a_tolerance_may_be_a_dimensionless_quantity():
    from faultslip.units import quantity

    assert ranges.check_tolerance(quantity(10, "percent")) == pytest.approx(0.1)
    assert ranges.check_tolerance(quantity(0.1, "")) == pytest.approx(0.1)
    with pytest.raises(InputError, match="got <Quantity"):
        ranges.check_tolerance(quantity(0.1, "m"))


@pytest.mark.parametrize("given", [0, 1, 1.5, -0.1, "0", "100 %", "ten", "", "nan", "inf", True, [0.1], "0.1 m"])
def test_a_tolerance_outside_0_and_1_is_one_sentence(given):
    with pytest.raises(InputError, match=r"^tolerance must be a relative error between 0 and 1 .*got .* \(here\)$"):
        ranges.check_tolerance(given, "here")


def test_every_front_door_takes_a_tolerance_as_text(cli):
    """A notebook's tolerance="10 %" is the command's --tolerance "10 %": the same method, the same answer."""
    import faultslip

    from_python = faultslip.run("lab_glass_dry.toml", tolerance="10 %")
    printed = cli("run", "configs/lab_glass_dry.toml", "--tolerance", "10 %", "--json")
    assert printed.code == 0 and printed.json["method"] == from_python.method == "closed_form"
    assert faultslip.models.estimate("lab_glass_dry.toml", tolerance="0.1").seconds > 0
    refused = cli("run", "configs/lab_glass_dry.toml", "--tolerance", "ten")
    assert refused.code == 2 and "got 'ten' (--tolerance)" in refused.err and "Traceback" not in refused.err
