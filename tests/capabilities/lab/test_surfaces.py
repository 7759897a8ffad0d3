"""Seed 000's rough surfaces: statistics, the Greenwood-Williamson model, contact by truncation."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.friction.contact import (contact_modulus, elastic_contact_hardness, greenwood_williamson,
                                        plasticity_index)
from faultslip.lab.surfaces import (Surface, approach_for_load, flat_like, gaussian_surface, read_surface, statistics,
                                    truncation_contact)


def test_seed_000_addendum_numbers_recomputed():
    """Seed 000 AD1.2 (its Table AD1: s = 2.37 um, R = 58.7 um; E = 210 kN/mm^2 (printed 'kN m^-2'), nu = 0.3,
    H = 208 kgf/mm^2): E' = 210 / (2 (1 - 0.09)) = 115.4 kN/mm^2 (printed 115); H' = 0.25 E' sqrt(s/R) = 5.80
    kN/mm^2 (printed 5.78, with E' rounded to 115); psi = 11.36 (printed 11.3)."""
    modulus = contact_modulus(210e9, 0.3)
    assert modulus == pytest.approx(115.38e9, rel=1e-4)
    assert elastic_contact_hardness(115e9, 2.37e-6, 58.7e-6) == pytest.approx(5.777e9, rel=1e-3)
    assert plasticity_index(modulus, 208 * 9.80665e6, 2.37e-6, 58.7e-6) == pytest.approx(11.36, abs=0.01)
    assert 30.0 / 280e6 == pytest.approx(0.107e-6, rel=3e-3)  # 30 N on 280 N/mm^2: the seed's 0.107 mm^2


def test_greenwood_williamson_against_its_closed_forms_for_exponential_heights():
    """phi = e^(-z/s)/s: n = eta A e^(-d/s), A = pi eta A R s e^(-d/s), P = sqrt(pi) E' sqrt(R) eta A s^1.5 e^(-d/s);
    so the mean pressure P/A = E' sqrt(s/R) / sqrt(pi) does not depend on the load."""
    eta, radius, spread, modulus = 1e10, 50e-6, 1e-6, 1e11
    d = np.array([0.0, 0.5e-6, 2e-6, 5e-6])
    gw = greenwood_williamson(d, eta, radius, spread, modulus, 1e-6, "exponential")
    np.testing.assert_allclose(gw["contacts"], eta * 1e-6 * np.exp(-d / spread), rtol=1e-12)
    np.testing.assert_allclose(gw["area"], math.pi * eta * 1e-6 * radius * spread * np.exp(-d / spread), rtol=1e-12)
    np.testing.assert_allclose(gw["load"], math.sqrt(math.pi) * modulus * math.sqrt(radius) * eta * 1e-6
                               * spread ** 1.5 * np.exp(-d / spread), rtol=1e-12)
    gaussian = greenwood_williamson(d, eta, radius, spread, modulus, 1e-6, "gaussian")
    assert np.all(np.diff(gaussian["load"]) < 0) and gaussian["contacts"][0] == pytest.approx(eta * 1e-6 / 2, rel=1e-8)


def test_a_single_summit_is_a_hertz_contact():
    """One summit (eta A = 1) at height z0 exactly, pressed by w: GW's load is Hertz's (4/3) E' sqrt(R) w^1.5."""
    from faultslip.friction.contact import _moments

    w, radius, modulus = 0.3e-6, 50e-6, 1e11
    # a narrow Gaussian of summit heights about w above the flat's position approximates one summit at w
    spread = 1e-10
    load = 4.0 / 3.0 * modulus * math.sqrt(radius) * _moments(np.array([-w]), spread, "gaussian", 1.5)[0]
    assert load == pytest.approx(4.0 / 3.0 * modulus * math.sqrt(radius) * w ** 1.5, rel=1e-6)


@settings(max_examples=12, deadline=None)
@given(st.floats(0.5e-6, 5e-6), st.floats(10e-6, 40e-6), st.integers(0, 1000))
def test_synthetic_surfaces_have_the_statistics_asked_for(rms, length, seed):
    """RMS exact; a Gaussian's CLA = sqrt(2/pi) RMS, skewness 0, kurtosis 3; beta* within the scatter of every seed on a 256-point map."""
    surface = gaussian_surface(rms, length, size=256, seed=seed)
    stats = statistics(surface)
    assert stats["rms"] == pytest.approx(rms, rel=1e-9)
    assert stats["cla"] / stats["rms"] == pytest.approx(math.sqrt(2 / math.pi), abs=0.03)
    # one map's moments scatter about the Gaussian's: over all 1001 seeds (the statistics do not depend on
    # rms or length, the spacing being length / 8) skewness has sd 0.066 and kurtosis 0.099; the bounds are
    # 5 sd (seed 855, a 4.8-sd map with skewness -0.314, broke the old 0.25)
    assert abs(stats["skewness"]) < 5 * 0.066 and abs(stats["kurtosis"] - 3) < 5 * 0.099
    # beta* scatters likewise: over all 1001 seeds its ratio to the length asked for has mean 1.031 and sd 0.086,
    # from 0.821 (seed 148) to 1.431 (seed 620; seed 300's 1.39 broke the old 30 %): the bounds hold every seed
    assert 0.8 <= stats["correlation_length"] / length <= 1.45


def test_synthetic_surfaces_are_gaussian_on_average():
    """Over 40 maps the mean skewness is 0 and the mean kurtosis 3, each within 4 standard errors (the moments of
    the heights, as statistics() defines them, without its autocorrelation: 0.3 s a map)."""
    def moments(height):
        deviation = height - height.mean()
        rms = np.sqrt(np.mean(deviation ** 2))
        return np.mean(deviation ** 3) / rms ** 3, np.mean(deviation ** 4) / rms ** 4

    surface = gaussian_surface(1e-6, 20e-6, size=256, seed=0)
    assert moments(surface.height) == pytest.approx((statistics(surface)["skewness"], statistics(surface)["kurtosis"]),
                                                     rel=1e-9)
    sampled = np.array([moments(gaussian_surface(1e-6, 20e-6, size=256, seed=seed).height) for seed in range(40)])
    assert abs(sampled[:, 0].mean()) < 4 * 0.066 / math.sqrt(40)
    assert abs(sampled[:, 1].mean() - 3) < 4 * 0.099 / math.sqrt(40)


def test_truncation_contact_grows_with_approach_and_conserves_volume():
    surface = gaussian_surface(2e-6, 20e-6, size=96, seed=3)
    approaches = np.linspace(0, 4e-6, 9)
    plain = truncation_contact(surface, approaches, flat_like(surface), 280e6, redistribute=False)
    raised = truncation_contact(surface, approaches, flat_like(surface), 280e6)
    assert np.all(np.diff(plain["area"]) >= 0) and plain["area"][0] == 0.0 < plain["area"][1]  # touching at 0
    assert np.all(raised["area"] <= plain["area"])  # the displaced volume raises the surface: less overlap
    np.testing.assert_allclose(raised["load"], 280e6 * raised["area"])  # plastic: L = p_c A (eq. 23)
    # against a flat, the overlap is the volume above the plane at height max - approach
    top = surface.height - surface.height.mean()
    volume = np.maximum(top - (top.max() - approaches[4]), 0).sum() * surface.cell_area
    assert plain["displaced_volume"][4] == pytest.approx(volume, rel=1e-12)
    at_load = approach_for_load(surface, 1.0, 280e6, flat_like(surface))
    assert 280e6 * at_load["area"] >= 1.0 and at_load["contacts"] >= 1


def test_readers_and_the_cli(cli, tmp_path):
    surface = read_surface("configs/example_surface.csv")
    assert surface.is_map and surface.height.shape == (64, 64) and surface.dx == pytest.approx(2.5e-6)
    profile = tmp_path / "p.csv"
    profile.write_text("x (mm),z (um)\n" + "\n".join(f"{0.01 * i},{math.sin(i / 3)}" for i in range(100)) + "\n",
                       encoding="utf-8")
    assert read_surface(profile).dx == pytest.approx(1e-5)
    out = cli("surface", "configs/example_surface.csv", "--modulus", "210 GPa", "--hardness", "208 kgf/mm^2",
              "--flow-pressure", "280 N/mm^2", "--load", "0.05 N", "--plot", tmp_path / "s.png", "--json")
    assert out.code == 0, out.err
    assert out.json["plasticity_index"] > 1 and out.json["contacts_at_load"] >= 1
    assert (tmp_path / "s.png").stat().st_size > 20_000
    synthetic = cli("surface", "--synthetic", "2 um", "20 um", "--size", "64", "--json").json
    assert synthetic["rms"]["value"] == pytest.approx(2e-6, rel=0.05)
    assert_clean_error(cli("surface"), "give a surface file")
    assert_clean_error(cli("surface", "configs/example_surface.csv", "--load", "1 N"), "--flow-pressure")
    bad = tmp_path / "bad.csv"
    bad.write_text("x (um),z (kg)\n" + "\n".join(f"{i},{i}" for i in range(20)) + "\n", encoding="utf-8")
    assert_clean_error(cli("surface", bad), "length")
    with pytest.raises(InputError, match="at least 8"):
        Surface(np.zeros(4), 1e-6)


def test_truncation_touches_the_summits_first_on_a_skewed_surface():
    """Issue 27, case 1: contact started at min(h + h'), so a flat touched a map's lowest cells first (on a
    positively skewed surface the area at 0.5 um was 120 times the true peaks'). Now the overlap at an
    approach delta is exactly the cells within delta of the highest point, against a flat, and within delta
    of the largest h + h' against the turned-over copy, whose first touch is where both are high."""
    base = gaussian_surface(1e-6, 20e-6, size=64, seed=5)
    skewed = Surface(np.exp(base.height / 1e-6) * 1e-6, base.dx, base.dy, "skewed")  # long upper tail
    top = skewed.height - skewed.height.mean()
    assert float(((top - top.mean()) ** 3).mean() / top.std() ** 3) > 1.0  # positively skewed
    for delta in (0.05e-6, 0.5e-6, 2e-6):
        flat = truncation_contact(skewed, [delta], flat_like(skewed), redistribute=False)
        assert flat["area"][0] == pytest.approx(np.count_nonzero(top >= top.max() - delta) * skewed.cell_area)
        reach = top + top[::-1, ::-1]
        copy = truncation_contact(skewed, [delta], redistribute=False)
        assert copy["area"][0] == pytest.approx(np.count_nonzero(reach >= reach.max() - delta) * skewed.cell_area)
    # the first contact is at the summit, not in a valley
    first = truncation_contact(skewed, [1e-12], flat_like(skewed), redistribute=False)
    assert first["area"][0] == skewed.cell_area and first["contacts"][0] == 1
