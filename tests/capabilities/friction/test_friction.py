"""The static-friction rate law (seed 003 eq. 2-18) and the other friction laws."""

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from faultslip.errors import InputError
from faultslip.friction.laws import (
    CallableKinetic,
    ConstantKinetic,
    LinearKinetic,
    PolynomialKinetic,
    RateLaw,
    TimeOfStickLaw,
    static_friction,
    static_friction_excess,
    time_of_stick_static_friction,
)

GRANODIORITE = dict(mu_so=0.65, mu_m=0.55, b=38.0, d=0.665)

mu_m_st = st.floats(0.05, 0.8)
drop_st = st.floats(1e-4, 0.4)
b_st = st.floats(1e-3, 1e4)
d_st = st.floats(0.2, 2.0)
rate_st = st.floats(1e-12, 1e3)


def test_limits_of_the_rate_law():
    assert static_friction(0.0, **GRANODIORITE) == pytest.approx(0.65)
    assert static_friction(1e30, **GRANODIORITE) == pytest.approx(0.55, abs=1e-12)
    # at b theta^d = 1/(mu_so - mu_m) the excess is halved
    rate = (1 / (0.1 * 38.0)) ** (1 / 0.665)
    assert static_friction_excess(rate, **GRANODIORITE) == pytest.approx(0.05)


def test_equal_static_and_kinetic_friction_gives_zero_excess_without_warnings():
    with np.errstate(all="raise"):
        assert static_friction_excess(1.0, 0.6, 0.6, 38.0, 0.665) == 0.0


@given(mu_m=mu_m_st, drop=drop_st, b=b_st, d=d_st, rate=rate_st, factor=st.floats(1.01, 100))
def test_static_friction_falls_as_loading_rate_rises(mu_m, drop, b, d, rate, factor):
    low = static_friction(rate, mu_m + drop, mu_m, b, d)
    high = static_friction(rate * factor, mu_m + drop, mu_m, b, d)
    assert mu_m <= high <= low <= mu_m + drop + 1e-15


def test_numpy_and_xarray_in_same_type_out():
    rates = np.logspace(-5, 3, 9)
    out = static_friction(rates, **GRANODIORITE)
    assert isinstance(out, np.ndarray) and out.shape == rates.shape
    da = xr.DataArray(rates, dims="loading_rate", coords={"loading_rate": rates})
    out_da = static_friction(da, **GRANODIORITE)
    assert isinstance(out_da, xr.DataArray) and out_da.dims == ("loading_rate",)
    np.testing.assert_allclose(out_da.values, out)
    # broadcasting parameters against rates keeps labelled dims
    mu_m = xr.DataArray([0.5, 0.55], dims="mu_m")
    assert set(static_friction(da, 0.65, mu_m, 38.0, 0.665).dims) == {"loading_rate", "mu_m"}


def test_rate_law_validation():
    with pytest.raises(InputError, match="mu_so .* must not be below mu_m"):
        RateLaw(0.5, 0.6)
    with pytest.raises(InputError, match="rate exponent d must be positive"):
        RateLaw(0.6, 0.5, 1.0, 0.0)
    with pytest.raises(InputError, match="finite"):
        RateLaw(float("nan"), 0.5)
    with pytest.raises(InputError, match="no stick-slip"):
        RateLaw(0.6, 0.6).require_stick_slip()


def test_time_of_stick_law_seed_002_eq_2():
    law = TimeOfStickLaw(mu_lower=0.3, mu_upper=0.4, growth_rate=2.0)
    assert law.limit(0.0, stick_time=0.0) == pytest.approx(0.3)
    assert law.limit(0.0, stick_time=0.5) == pytest.approx(0.3 + 0.1 * (1 - np.exp(-1.0)))
    assert time_of_stick_static_friction(1e9, 0.3, 0.4, 2.0) == pytest.approx(0.4)
    with pytest.raises(InputError):
        TimeOfStickLaw(0.5, 0.4, 1.0)


def test_kinetic_laws():
    assert ConstantKinetic(0.5)(np.array([0.0, 1.0])).tolist() == [0.5, 0.5]
    linear = LinearKinetic(0.5, -0.2)
    assert linear(2.0) == pytest.approx(0.1) and linear.slope == -0.2
    poly = PolynomialKinetic([0.5, -0.3, 0.1])
    assert poly(2.0) == pytest.approx(0.5 - 0.6 + 0.4)
    assert poly.derivative(2.0) == pytest.approx(-0.3 + 0.4)
    assert poly.mu_m == 0.5 and poly.slope == -0.3
    call = CallableKinetic(lambda u: 0.5 + 0.1 * np.tanh(u), name="tanh")
    assert call.slope == pytest.approx(0.1, rel=1e-5)
    with pytest.raises(InputError):
        CallableKinetic(lambda u: -1.0 + 0 * u)
