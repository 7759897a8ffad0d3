"""Magnitude-frequency distributions that conserve a fault's moment rate.

A fault of area A slipping at V releases the moment rate G A V (N m per year here). faultslip predicts
its characteristic event, Mw with recurrence T, whose moment rate M0(Mw)/T is that same G A V (Aki 1966,
with slip per event = V T). A hazard engine wants a distribution of magnitudes instead, with the same
budget. Three are built, each on bins of width ``bin_width`` with rates in events per year, and each
scaled so that

    sum_i rate_i M0(m_i) = G A V,     M0(m) = 10^(1.5 m + c) N m,

with ``m_i`` the bin centres and c the moment constant (9.1, faultslip's Mw convention; OpenQuake's MFD
code uses Hanks & Kanamori's 9.05, so pass ``moment_constant=9.05`` to balance the budget as the engine
will count it):

- :func:`youngs_coppersmith_1985`, the characteristic model of Youngs & Coppersmith (1985, BSSA 75,
  939-964, eqs. 10-17): an exponential (Gutenberg-Richter) part from ``min_magnitude`` to Mc - 0.25 and a
  box of constant density on [Mc - 0.25, Mc + 0.25], whose density equals the exponential density at
  Mc - 1.25 (their Delta M1 = 1, Delta M2 = 0.5). Bins are anchored at Mc + 0.25, so the box fills whole
  bins;
- :func:`truncated_gutenberg_richter`, with rates 10^(a - b m_lo) - 10^(a - b m_hi) per bin between
  magnitude bounds on multiples of the bin width, as OpenQuake's ``truncGutenbergRichterMFD`` discretises
  it, the a-value set by the moment budget;
- :func:`single_bin`, the characteristic event alone: one bin at Mw with the rate of the budget.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from faultslip import ranges
from faultslip.errors import InputError
from faultslip.datasets import ToXarray
from faultslip.units import takes_units

MOMENT_CONSTANT = 9.1  # faultslip's Mw = (2/3)(log10 M0 - 9.1) (fault.scaling.MW_CONSTANT)
BIN_WIDTH = 0.1
B_VALUE = 1.0
MIN_MAGNITUDE = 5.0
CHARACTERISTIC_HALF_WIDTH = 0.25  # Youngs & Coppersmith's Delta M2 / 2
CHARACTERISTIC_OFFSET = 1.0  # their Delta M1: the box density is the exponential one at Mc - 0.25 - 1
KINDS = ("characteristic", "truncated_gr", "single_bin")


def moment(magnitude, moment_constant: float = MOMENT_CONSTANT):
    """Seismic moment M0 = 10^(1.5 Mw + c) in N m."""
    return 10.0 ** (1.5 * np.asarray(magnitude, dtype=float) + moment_constant)


@dataclass(frozen=True)
class MagnitudeFrequency(ToXarray):
    """Incremental annual rates on evenly spaced magnitude bins (first bin centred on ``min_magnitude``)."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'min_magnitude': '1', 'bin_width': '1', 'rates': '1/yr', 'moment_constant': '1'}
    DIMENSIONS = {'rates': 'bin'}

    kind: str
    min_magnitude: float
    bin_width: float
    rates: np.ndarray  # events per year, one per bin
    moment_constant: float
    parameters: dict = field(default_factory=dict)  # what defines it: b-value, a-value, bounds, Mc

    @property
    def magnitudes(self) -> np.ndarray:
        """The bin centres."""
        return self.min_magnitude + self.bin_width * np.arange(len(self.rates))

    def moment_rate(self, moment_constant: float | None = None) -> float:
        """Sum of rate times M0 at the bin centres (N m per year)."""
        constant = self.moment_constant if moment_constant is None else moment_constant
        return float(np.sum(self.rates * moment(self.magnitudes, constant)))

    def cumulative(self) -> np.ndarray:
        """Annual rate of events in each bin or above."""
        return np.cumsum(self.rates[::-1])[::-1]

    def as_dict(self) -> dict:
        return {"kind": self.kind, "min_magnitude": self.min_magnitude, "bin_width": self.bin_width,
                "rates": {"value": [float(r) for r in self.rates], "units": "1/yr"},
                "moment_rate": {"value": self.moment_rate(), "units": "N m/yr"},
                "moment_constant": self.moment_constant, **self.parameters}


def check_parameters(b_value: float = B_VALUE, bin_width: float = BIN_WIDTH, **magnitudes) -> None:
    """Refuse a b-value, bin width or magnitude no distribution can take (before any work), by the
    ranges every input of these kinds passes (:data:`faultslip.ranges.BOUNDS`)."""
    for name, value in (("b_value", b_value), ("bin_width", bin_width), *magnitudes.items()):
        if np.ndim(value) != 0:  # a distribution has one of each: a list is not read as its first
            raise InputError(f"the {name.replace('_', ' ')} must be one number, got {value!r}")
    ranges.check("b_value", b_value)
    ranges.check("bin_width", bin_width)
    for name, value in magnitudes.items():
        ranges.check(name if name in ranges.RULES else "min_magnitude", value, name.replace("_", " "))


def _check(moment_rate, b_value, bin_width, **magnitudes) -> None:
    if not (isinstance(moment_rate, numbers.Real) and math.isfinite(moment_rate) and moment_rate > 0):
        raise InputError(f"the moment rate must be positive and finite, got {moment_rate!r} N m/yr")
    check_parameters(b_value, bin_width, **magnitudes)


def _balanced(kind, edges, shape, moment_rate, moment_constant, parameters) -> MagnitudeFrequency:
    """Scale the rates' ``shape`` on bins with ``edges`` so that they release ``moment_rate``."""
    centres = 0.5 * (edges[1:] + edges[:-1])
    scale = moment_rate / float(np.sum(shape * moment(centres, moment_constant)))
    width = float(edges[1] - edges[0])
    return MagnitudeFrequency(kind, float(centres[0]), width, shape * scale, moment_constant,
                              parameters | {"scale": scale})


@takes_units(moment_rate=("moment_rate", "N*m/yr"))
def youngs_coppersmith_1985(moment_rate: float, characteristic_magnitude: float,
                            min_magnitude: float = MIN_MAGNITUDE, b_value: float = B_VALUE,
                            bin_width: float = BIN_WIDTH,
                            moment_constant: float = MOMENT_CONSTANT) -> MagnitudeFrequency:
    """The Youngs & Coppersmith (1985) characteristic distribution releasing ``moment_rate`` (N m/yr).

    Density n(m) = beta 10^(-b m) (beta = b ln 10) for min <= m < Mc - 0.25 and the constant
    beta 10^(-b (Mc - 1.25)) on [Mc - 0.25, Mc + 0.25], integrated exactly over each bin and scaled to the
    budget. The bins run down from Mc + 0.25 to the last edge at or above ``min_magnitude``.

    Parameters
    ----------
    moment_rate : float
        The budget (N m/yr).
    characteristic_magnitude : float
        Mc.
    min_magnitude : float
        Mw.
    b_value : float
        b.
    bin_width : float
        The bins' width.
    moment_constant : float
        The constant of Mw.

    Returns
    -------
    MagnitudeFrequency
        Bin magnitudes and rates (1/yr).
    """
    _check(moment_rate, b_value, bin_width, characteristic_magnitude=characteristic_magnitude,
           min_magnitude=min_magnitude)
    top = characteristic_magnitude + CHARACTERISTIC_HALF_WIDTH
    box_low = characteristic_magnitude - CHARACTERISTIC_HALF_WIDTH
    count = int(math.floor((top - min_magnitude) / bin_width + 1e-9))
    if count < 1:
        raise InputError(f"the minimum magnitude {min_magnitude:g} is above the characteristic box's top "
                         f"{top:.3f} (Mc {characteristic_magnitude:.3f} + 0.25): no bin to fill")
    edges = top - bin_width * np.arange(count, -1, -1)
    low, high = edges[:-1], edges[1:]
    # exponential part on [low, min(high, box_low)], box part on [max(low, box_low), high]
    exponential_high = np.minimum(high, box_low)
    exponential = np.where(exponential_high > low, 10.0 ** (-b_value * low) - 10.0 ** (-b_value * exponential_high),
                           0.0)
    box_density = b_value * math.log(10.0) * 10.0 ** (-b_value * (box_low - CHARACTERISTIC_OFFSET))
    box = box_density * np.clip(high - np.maximum(low, box_low), 0.0, None)
    parameters = {"characteristic_magnitude": characteristic_magnitude, "b_value": b_value,
                  "requested_min_magnitude": min_magnitude}
    return _balanced("characteristic", edges, exponential + box, moment_rate, moment_constant, parameters)


@takes_units(moment_rate=("moment_rate", "N*m/yr"))
def truncated_gutenberg_richter(moment_rate: float, max_magnitude: float, min_magnitude: float = MIN_MAGNITUDE,
                                b_value: float = B_VALUE, bin_width: float = BIN_WIDTH,
                                moment_constant: float = MOMENT_CONSTANT) -> MagnitudeFrequency:
    """A truncated Gutenberg-Richter distribution releasing ``moment_rate`` (N m/yr).

    The bounds are put on multiples of ``bin_width`` (the engine does the same), each bin's rate is
    10^(a - b m_lo) - 10^(a - b m_hi), and the a-value (of the cumulative rate, events per year) is the one
    that meets the budget: a = log10(budget / sum_i (10^(-b lo_i) - 10^(-b hi_i)) M0(m_i)).

    Parameters
    ----------
    moment_rate : float
        The budget (N m/yr).
    max_magnitude, min_magnitude : float
        The bounds (Mw).
    b_value : float
        b.
    bin_width : float
        The bins' width.
    moment_constant : float
        The constant of Mw.

    Returns
    -------
    MagnitudeFrequency
        Bin magnitudes and rates (1/yr).
    """
    _check(moment_rate, b_value, bin_width, max_magnitude=max_magnitude, min_magnitude=min_magnitude)
    low_edge = round(min_magnitude / bin_width) * bin_width
    high_edge = round(max_magnitude / bin_width) * bin_width
    count = int(round((high_edge - low_edge) / bin_width))
    if count < 1:
        raise InputError(f"the truncated Gutenberg-Richter bounds {min_magnitude:g} to {max_magnitude:g} leave no "
                         f"bin of width {bin_width:g}: lower the minimum magnitude")
    edges = low_edge + bin_width * np.arange(count + 1)
    shape = 10.0 ** (-b_value * edges[:-1]) - 10.0 ** (-b_value * edges[1:])
    result = _balanced("truncated_gr", edges, shape, moment_rate, moment_constant,
                       {"b_value": b_value, "min_magnitude_edge": float(edges[0]),
                        "max_magnitude_edge": float(edges[-1])})
    return MagnitudeFrequency(result.kind, result.min_magnitude, result.bin_width, result.rates,
                              result.moment_constant,
                              result.parameters | {"a_value": math.log10(result.parameters["scale"])})


def continuous_moment_rate(distribution: MagnitudeFrequency, moment_constant: float | None = None) -> float:
    """The moment rate of a truncated Gutenberg-Richter distribution integrated over its continuous density
    between its bounds (N m per year), as OpenQuake's ``TruncatedGRMFD`` counts it; the bins balance the sum at
    their centres instead (:meth:`MagnitudeFrequency.moment_rate`).

    With the density b ln10 10^(a - b m) and M0(m) = 10^(1.5 m + c),

        M0_rate = 10^(a + c) b / (1.5 - b) [10^((1.5 - b) m_max) - 10^((1.5 - b) m_min)],

    and 10^(a + c) b ln10 (m_max - m_min) at b = 1.5. Per bin of width h the two differ by the factor
    [sinh(x) / x] [y / sinh(y)], x = (1.5 - b) ln10 h / 2, y = b ln10 h / 2, whatever the bounds.

    Parameters
    ----------
    distribution : MagnitudeFrequency
        A ``truncated_gr`` distribution (its a-value, b-value and bin-edge bounds).
    moment_constant : float, optional
        The constant c of Mw; the distribution's own by default.

    Returns
    -------
    float
        The moment rate (N m/yr).
    """
    if distribution.kind != "truncated_gr":
        raise InputError(f"a continuous moment rate is defined for a truncated_gr distribution, not "
                         f"{distribution.kind!r}")
    constant = distribution.moment_constant if moment_constant is None else moment_constant
    found = distribution.parameters
    b_value, low, high = found["b_value"], found["min_magnitude_edge"], found["max_magnitude_edge"]
    exponent, span = (1.5 - b_value) * math.log(10.0), (high - low)
    # 10^(e m_max) - 10^(e m_min) through expm1, which keeps its digits as b nears 1.5
    growth = span if exponent == 0.0 else math.expm1(exponent * span) / exponent
    return float(10.0 ** (found["a_value"] + constant + (1.5 - b_value) * low) * b_value * math.log(10.0) * growth)


@takes_units(moment_rate=("moment_rate", "N*m/yr"))
def single_bin(moment_rate: float, magnitude: float, bin_width: float = BIN_WIDTH,
               moment_constant: float = MOMENT_CONSTANT) -> MagnitudeFrequency:
    """The characteristic event alone: one bin centred on Mw with the rate budget / M0(Mw) (= 1/T when the
    budget is faultslip's own).

    Parameters
    ----------
    moment_rate : float
        The moment budget (N m/yr).
    magnitude : float
        Mw.
    bin_width : float
        The bin's width.
    moment_constant : float
        The constant of Mw.

    Returns
    -------
    MagnitudeFrequency
        Bin magnitudes and rates (1/yr).
    """
    _check(moment_rate, B_VALUE, bin_width, magnitude=magnitude)
    rate = moment_rate / float(moment(magnitude, moment_constant))
    return MagnitudeFrequency("single_bin", float(magnitude), bin_width, np.array([rate]), moment_constant,
                              {"magnitude": float(magnitude)})


def build(kind: str, moment_rate: float, magnitude: float, min_magnitude: float = MIN_MAGNITUDE,
          b_value: float = B_VALUE, bin_width: float = BIN_WIDTH,
          moment_constant: float = MOMENT_CONSTANT) -> MagnitudeFrequency:
    """One of :data:`KINDS` for an event of ``magnitude``: its Mc (characteristic), its upper bound
    (truncated_gr, to the nearest bin edge) or its bin (single_bin)."""
    if kind == "characteristic":
        return youngs_coppersmith_1985(moment_rate, magnitude, min_magnitude, b_value, bin_width, moment_constant)
    if kind == "truncated_gr":
        return truncated_gutenberg_richter(moment_rate, magnitude, min_magnitude, b_value, bin_width, moment_constant)
    if kind == "single_bin":
        return single_bin(moment_rate, magnitude, bin_width, moment_constant)
    raise InputError(f"the magnitude-frequency distribution must be one of {', '.join(KINDS)}, got {kind!r}")
