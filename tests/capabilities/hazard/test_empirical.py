"""Empirical scaling (W&C 1994 Tables 2A-2B, Leonard 2010 Table 6) and its comparison with the physics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.fault import empirical
from faultslip.fault.empirical import (SLIP_TYPES, WELLS_COPPERSMITH_1994, average_displacement, compare,
                                       leonard_average_displacement, leonard_magnitude_from_area, magnitude_from_area,
                                       magnitude_from_length, rupture_area, rupture_length)

KM = 1e3


def test_worked_values_of_the_tables():
    """Each relation evaluated by hand from W&C 1994's printed a and b (provenance: Tables 2A-2B):
    strike-slip AD at Mw 7 = 10^(-6.32 + 6.30) = 0.955 m; all-types area at Mw 7 = 10^(-3.49 + 6.37) km^2 =
    759 km^2; strike-slip Mw for a 100 km surface rupture = 5.16 + 1.12 x 2 = 7.40; reverse Mw for 1000 km^2
    = 4.33 + 0.90 x 3 = 7.03."""
    assert average_displacement(7.0, "strike-slip")[0] == pytest.approx(10 ** -0.02, rel=1e-12)
    assert rupture_area(7.0, "all")[0] == pytest.approx(10 ** 2.88 * 1e6, rel=1e-12)
    assert magnitude_from_length(100 * KM, "strike-slip") == pytest.approx((7.40, 0.28), rel=1e-12)
    assert magnitude_from_area(1000 * KM ** 2, "reverse")[0] == pytest.approx(7.03, rel=1e-12)
    assert rupture_length(7.0, "normal")[0] == pytest.approx(10 ** 1.49 * KM, rel=1e-12)


@pytest.mark.parametrize("slip_type", SLIP_TYPES)
def test_the_forward_and_inverse_regressions_nearly_invert(slip_type):
    """W&C fit y(x) and x(y) separately (each by least squares), so they are not exact inverses; over
    Mw 6-7.5 they agree within their scatter: Mw(RA(Mw)) and Mw(SRL(Mw)) within 1.5 sigma of Mw (measured:
    at most 0.34, normal faults at Mw 7.5, near the top of W&C's normal-fault data)."""
    for magnitude in np.linspace(6.0, 7.5, 7):
        from_area, sigma = magnitude_from_area(rupture_area(magnitude, slip_type)[0], slip_type)
        assert abs(from_area - magnitude) < 1.5 * sigma
        from_length, sigma = magnitude_from_length(rupture_length(magnitude, slip_type)[0], slip_type)
        assert abs(from_length - magnitude) < 1.5 * sigma


def test_the_strike_slip_relations_conserve_moment_to_their_scatter():
    """M0 = mu A AD from W&C's own AD(Mw) and RA(Mw), mu = 3e10 Pa, against 10^(1.5 Mw + 9.1): short by a
    factor 3.7 at Mw 6 and 1.3 at 7.5 (measured). AD is displacement at the surface, which falls short of
    the slip at depth in smaller events; the shortfall stays within two sigma of AD (a factor 3.6 each)."""
    for magnitude in np.linspace(6.0, 7.5, 7):
        moment = 3e10 * rupture_area(magnitude, "strike-slip")[0] * average_displacement(magnitude, "strike-slip")[0]
        shortfall = (1.5 * magnitude + 9.1) - math.log10(moment)
        assert 0 < shortfall < 2 * 0.28 + 0.01


def test_leonard_displacement_reproduces_his_moment_exactly():
    area = 430 * KM * 12 * KM
    magnitude = leonard_magnitude_from_area(area, "strike-slip")
    # Table 6 prints 3.99; computed from Table 5's C2 = 3.7e-5 it is 3.9911 (tests/capabilities/hazard/test_hazard.py)
    assert magnitude == pytest.approx(math.log10(5160) + 3.99, abs=0.005)
    moment = empirical.LEONARD_SHEAR_MODULUS * area * leonard_average_displacement(area, "strike-slip")
    assert math.log10(moment) == pytest.approx(1.5 * magnitude + 9.1, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.floats(5.0, 8.5), st.floats(0.01, 1.0), st.sampled_from(SLIP_TYPES))
def test_displacements_grow_with_magnitude_and_z_follows_the_ratio(magnitude, step, slip_type):
    small, _ = average_displacement(magnitude, slip_type)
    large, _ = average_displacement(magnitude + step, slip_type)
    assert large > small
    rows = compare(2.0, magnitude, 200 * KM, 15 * KM, slip_type if slip_type != "all" else "strike-slip")
    for row in rows:
        if row.z_score is not None and not row.is_magnitude:
            assert (row.z_score > 0) == (row.ratio > 1)


def test_the_1906_fault_report_places_the_prediction_beside_the_scaling_relations(cli):
    out = cli("run", "--json").json
    rows = [value for key, value in out.items() if key.startswith("empirical_")]
    assert [row["relation"] for row in rows][:3] == ["W&C 1994 AD(Mw), strike-slip", "Leonard 2010 D(A), strike-slip",
                                                     "W&C 1994 Mw(SRL), strike-slip"]
    slip = rows[0]
    # slip per event 6.43 m at Mw 7.88: W&C expect 10^(-6.32 + 0.90 x 7.88) = 5.95 m
    assert slip["expected"]["value"] == pytest.approx(10 ** (-6.32 + 0.90 * out["moment_magnitude"]), rel=1e-12)
    assert slip["ratio"] == pytest.approx(out["slip_per_event"]["value"] / slip["expected"]["value"], rel=1e-12)
    assert abs(slip["z_score"]) < 1 and rows[1]["z_score"] is None


def test_bad_inputs_are_refused():
    with pytest.raises(InputError, match="slip type"):
        average_displacement(7.0, "oblique")
    with pytest.raises(InputError, match="positive"):
        magnitude_from_length(-1.0)
    with pytest.raises(InputError, match="Leonard"):
        leonard_magnitude_from_area(1e9, "subduction")
    assert set(WELLS_COPPERSMITH_1994["average_displacement_from_magnitude"]) == set(SLIP_TYPES)


@given(st.floats(1.0, 2000.0))
@settings(max_examples=30, deadline=None)
def test_lengths_and_areas_with_units_are_their_si_values(length_km):
    """As MetPy's calc takes Quantities: "L km", a pint Quantity in miles and L x 1000 m give one magnitude; an
    area in km^2 is 1e6 m^2. Bare numbers stay SI, as documented."""
    from faultslip.units import quantity

    expected = magnitude_from_length(length_km * KM)[0]
    assert magnitude_from_length(f"{length_km!r} km")[0] == pytest.approx(expected, rel=1e-12)
    assert magnitude_from_length(quantity(length_km / 1.609344, "mi"))[0] == pytest.approx(expected, rel=1e-12)
    assert magnitude_from_area(f"{length_km!r} km^2")[0] == pytest.approx(magnitude_from_area(length_km * 1e6)[0],
                                                                          rel=1e-12)
    assert empirical.leonard_magnitude_from_length(f"{length_km!r} km") == pytest.approx(
        empirical.leonard_magnitude_from_length(length_km * KM), rel=1e-12)


@pytest.mark.parametrize("call, said", [
    (lambda: magnitude_from_length("x"), "surface rupture length"), (lambda: magnitude_from_length("7 kg"), "length"),
    (lambda: magnitude_from_area("7 km"), "must be an area"), (lambda: rupture_length("seven"), "magnitude"),
    (lambda: empirical.leonard_width(float("nan")), "finite"),
    (lambda: __import__("faultslip").hazard.truncated_gutenberg_richter(1e17, []), "one number"),
    (lambda: __import__("faultslip").hazard.youngs_coppersmith_1985("1e17", 7.0), "moment rate"),
    (lambda: __import__("faultslip").hazard.single_bin(1e17, "seven"), "must be a number")])
def test_a_relation_given_text_or_a_list_where_it_takes_a_number_says_so_in_one_sentence(call, said):
    """numpy's ValueError ("could not convert string to float") and math's TypeError had escaped these."""
    with pytest.raises(InputError, match=said):
        call()


def test_studies_and_maps_carry_the_empirical_variables(tmp_path, cli):
    import xarray as xr

    result = cli("map", "configs/san_andreas_map.toml", "-o", tmp_path / "m.nc", "--json")
    assert result.code == 0, result.err
    with xr.open_dataset(tmp_path / "m.nc") as data:
        ratio = data["empirical_slip_ratio"].values
        expected = 10 ** (-6.32 + 0.90 * data["moment_magnitude"].values)
        finite = np.isfinite(ratio)
        np.testing.assert_allclose(ratio[finite], (data["slip_per_event"].values / expected)[finite], rtol=1e-12)
        assert data["empirical_slip_z"].attrs["units"] == "1"


def test_a_rupture_outside_the_relations_range_is_said_not_divided_by_zero(cli):
    """Found by the CLI fuzzer: a 1e-300 m rupture put W&C's expected displacement beyond floating point and
    the ratio divided by zero. The comparison now says it is out of range, and the JSON stays valid; at the command
    line such a length is now refused at the door (faultslip.ranges.BOUNDS: 1 mm to 10,000 km), and the shortest
    it takes still gives rows that are finite or say they are out of range."""
    rows = compare(1.0, -330.0, 1e-300, 12e3)
    assert math.isnan(rows[1].ratio) or rows[1].ratio > 0
    flags = ("fault", "--lithology", "granite", "--zone-width", "13 mi", "--shear-stress", "250 bar", "--slip-rate",
             "2 in/yr", "--shear-modulus", "0.25e6 bar", "--depth", "12 km", "--mu-so", "0.65", "--mu-m", "0.55")
    assert_clean_error(cli(*flags, "--rupture-length", "1e-300 m"), "rupture length must lie between")
    out = cli(*flags, "--rupture-length", "1 mm", "--json")
    assert out.code == 0, out.err
    # Leonard's relations are now evaluated in logarithms and no longer underflow; every row is either a finite
    # comparison or says that it is out of range
    rows = [value for key, value in out.json.items() if key.startswith("empirical_")]
    assert rows and all("outside the relation's range" in row["summary"] or
                        (row["ratio"] is not None and math.isfinite(row["ratio"])) or row["expected"]["value"] is not None
                        for row in rows)
