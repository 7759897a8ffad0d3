"""The one result every model family returns: quantities with units, the method, its declared error, and the
family's report, dataset and figure (issue 32's contract, in the spirit of scikit-learn's estimator API)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from faultslip.errors import InputError
from faultslip.io.report import Report
from faultslip.units import quantity


@dataclass
class Result:
    """What :func:`faultslip.run` and :func:`faultslip.simulate` return, whatever the model family.

    ``result["slip_per_event"]`` is a pint Quantity (or a plain value for a label such as the
    regime); ``method``, ``method_reason`` and ``estimated_relative_error`` say how it was
    computed; :meth:`report` is what the CLI prints, :meth:`to_xarray` what it writes (CF
    attributes), :meth:`plot` the family's figure and :meth:`time_series` the run, where the
    family simulates.
    """

    family: str
    summary: Report
    series: object = None  # an xarray Dataset of the run, where the family simulated
    figure: Callable | None = None  # () -> matplotlib Figure
    extras: dict = field(default_factory=dict)  # family capabilities, e.g. "stream" and "events" of the seed law

    @property
    def method(self) -> str | None:
        return self.summary["method"] if "method" in self.summary else None

    @property
    def method_reason(self) -> str | None:
        return self.summary["method_reason"] if "method_reason" in self.summary else None

    @property
    def estimated_relative_error(self) -> float | None:
        for key in ("estimated_relative_error", "estimated_error"):
            if key in self.summary:
                return self.summary[key]
        return None

    def keys(self) -> list[str]:
        return [item.key for item in self.summary.items]

    def __getitem__(self, key):
        """A reported value: a pint Quantity where it has units, else the plain value."""
        for item in self.summary.items:
            if item.key == key:
                if item.is_quantity and isinstance(item.value, (int, float)) and not isinstance(item.value, bool):
                    return quantity(item.value, "dimensionless" if item.units in ("1", "") else item.units)
                return item.value
        raise KeyError(f"{key!r} is not among this result's values ({', '.join(self.keys())})")

    def report(self) -> Report:
        """The text and JSON report the CLI prints."""
        return self.summary

    def to_xarray(self):
        """The result as an xarray Dataset, the schema the CLI writes: a simulation's time series, or else every
        scalar quantity as a 0-d variable with its ``units``; the method and its declared error as attributes."""
        import xarray as xr  # heavy: imported where used

        variables, ranges = {}, {}
        for item in (self.summary.items if self.series is None else ()):  # a run's time series is its data
            value = item.value
            if _is_range(item):  # a 95 % range: the 2.5 and 97.5 % quantiles, beside the value it qualifies
                ranges[item.key] = (("quantile",), [float(v) for v in value],
                                    {"long_name": item.label, "units": item.units or "1"})
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                continue
            # CF: a dimensionless number (a ratio, a count, a friction coefficient) has units "1"
            attrs = {"long_name": item.label, "units": item.units if item.is_quantity and item.units else "1"}
            variables[item.key] = ((), float(value), attrs)
        for key in ranges:  # CF ancillary variables: the value names its uncertainty
            base = key.removesuffix("_95")
            if base in variables:
                variables[base][2]["ancillary_variables"] = key
        dataset = self.series.copy() if self.series is not None else xr.Dataset()
        dataset = dataset.assign(**{name: xr.Variable(*spec) for name, spec in variables.items()})
        if ranges:
            dataset = dataset.assign_coords(quantile=("quantile", [0.025, 0.975], {
                "long_name": "probability of the quantile", "units": "1"}))
            dataset = dataset.assign(**{name: xr.Variable(*spec) for name, spec in ranges.items()})
        dataset.attrs.update({key: value for key, value in {
            "title": self.summary.title, "faultslip_family": self.family, "method": self.method,
            "method_reason": self.method_reason, "estimated_relative_error": self.estimated_relative_error,
        }.items() if value is not None})
        dataset.attrs.setdefault("Conventions", "CF-1.8")
        return dataset

    def time_series(self):
        """The run's time series (an xarray Dataset); only a simulation has one."""
        if self.series is None:
            raise InputError(f"this {self.family} result has no time series; faultslip.simulate(scene) records one")
        return self.series

    def plot(self):
        """The family's figure of this result (a matplotlib Figure)."""
        if self.figure is None:
            raise InputError(f"this {self.family} result has no figure; faultslip.simulate(scene) draws one")
        return self.figure()

    def _repr_pretty_(self, printer, cycle):  # IPython shows the report
        printer.text(self.summary.to_text())

    def __str__(self) -> str:
        return self.summary.to_text()


def _is_range(item) -> bool:
    """A reported 95 % range: two finite numbers under a key ending in _95."""
    value = item.value
    return (item.key.endswith("_95") and isinstance(value, (list, tuple)) and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))
