"""The one result every model family returns: typed values with units, the method, its declared error, and the
family's dataset and figure (issue 32's contract, in the spirit of scikit-learn's estimator API and pvlib's
``ModelChainResult``).

A family builds its answer as a :class:`~faultslip.io.report.Report` (values with units, labels, notes); the
Result takes the values out of it once, as typed entries, and derives the report, the Dataset and the JSON from
them. ``result.values`` is a mapping of pint Quantities; nothing is found by scanning text.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Callable

from faultslip.errors import InputError
from faultslip.io.report import Item, Report
from faultslip.units import quantity


#: The spellings of a pure number's units (UDUNITS "1", none, pint's).
DIMENSIONLESS = frozenset({"1", "", "dimensionless"})


@dataclass(frozen=True)
class Entry:
    """One value of a Result: the number (SI) or text, its units (None: a plain value) and how it is shown."""

    key: str
    value: object
    units: str | None
    label: str
    also: tuple = ()
    error: float | None = None
    in_text: bool = True

    @property
    def is_number(self) -> bool:
        return isinstance(self.value, (int, float)) and not isinstance(self.value, bool)

    @property
    def is_range(self) -> bool:
        """A 95 % range: two numbers under a key ending in _95."""
        value = self.value
        return (self.key.endswith("_95") and isinstance(value, (list, tuple)) and len(value) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))

    @property
    def is_pair(self) -> bool:
        """Two numbers with units (a low and a high: a 95 % range, or a range of values such as
        ``recurrence_range``); a high of None is a range with no upper end."""
        value = self.value
        return (self.units is not None and isinstance(value, (list, tuple)) and len(value) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value[:1])
                and (value[1] is None or isinstance(value[1], (int, float)) and not isinstance(value[1], bool)))

    def typed(self):
        """The value as a pint Quantity where it has units (a range as a pair of them), else as it is."""
        if self.units is None:
            return self.value
        unit = "dimensionless" if self.units in ("1", "") else self.units
        if self.is_number:
            return quantity(self.value, unit)
        if self.is_range or self.is_pair:
            return tuple(None if v is None else quantity(v, unit) for v in self.value)
        return self.value


class Values(Mapping):
    """A Result's values by key: pint Quantities where they have units, plain values otherwise (a regime)."""

    def __init__(self, entries: dict):
        self._entries = entries

    def __getitem__(self, key):
        if key not in self._entries:
            raise KeyError(f"{key!r} is not among this result's values ({', '.join(self._entries)})")
        return self._entries[key].typed()

    def __iter__(self):
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)


class Result:
    """What :func:`faultslip.run` and :func:`faultslip.simulate` return, whatever the model family.

    Attributes
    ----------
    family : str
        The model family (``faultslip.contract.DECLARATIONS``).
    values : Mapping
        Every value by key: a pint Quantity where it has units (``result.values["slip_per_event"]``, also
        ``result["slip_per_event"]``), a plain value for a label such as the regime; a 95 % range (``*_95``)
        is a pair of Quantities.
    method, method_reason : str or None
        The method that computed the values, and why it was chosen.
    estimated_relative_error : float or None
        The method's declared relative error (what ``auto`` compared with the tolerance).
    notes : list of str
        What the reader should know: the scene's origin, sources, caveats.
    series : xarray.Dataset or None
        A simulation's time series.
    extras : dict
        Family capabilities (the seed law's ``stream`` and ``events``, a sweep's arrays, ...).
    tolerance : float or None
        The relative error the method was chosen for where no tolerance was passed: the scene's ``[method]``
        tolerance or the family's default. :func:`faultslip.run` judges the answer against it (``meets_tolerance``)
        as against a tolerance passed; None where no tolerance chose the method.

    :meth:`report` is what the CLI prints, :meth:`to_xarray` what it writes (CF attributes), :meth:`plot` the
    family's figure and :meth:`time_series` the run, where the family simulates.
    """

    def __init__(self, family: str, summary: Report, series=None, figure: Callable | None = None,
                 extras: dict | None = None, tolerance: float | None = None):
        self.family = family
        self.tolerance = tolerance  # what chose the method when the caller gave none (judge_tolerance)
        self.title = summary.title
        self._entries = {item.key: Entry(item.key, item.value, item.units, item.label, item.also, item.error,
                                         item.in_text) for item in summary.items}
        self._sections = dict(summary.sections)  # heading -> index of its first entry
        self.notes = list(summary.notes)
        self.series = series  # an xarray Dataset of the run, where the family simulated
        self.figure = figure  # () -> matplotlib Figure
        self.extras = dict(extras or {})

    # --- typed access ---------------------------------------------------------------------------------------

    @property
    def values(self) -> Values:
        return Values(self._entries)

    def _plain(self, key):
        entry = self._entries.get(key)
        return None if entry is None else entry.value

    def si(self, key):
        """A value as the family stored it: a number in SI (its ``units``), or a plain value; None where absent.
        No pint: for code that must stay light (a cycle run loads no unit registry)."""
        return self._plain(key)

    def number(self, key: str, units: str):
        """A value in ``units``: the stored number where it is stored in them (no pint: a sweep's cells load no
        unit registry), converted by pint where they differ; a plain value as it is; None where absent.

        Parameters
        ----------
        key : str
            The value's key.
        units : str
            The units wanted (UDUNITS; ``"1"`` for a number).

        Returns
        -------
        float, str or None
            The number in ``units``, or the plain value (a regime's text).
        """
        entry = self._entries.get(key)
        if entry is None or entry.value is None or entry.units is None or not entry.is_number:
            return None if entry is None else entry.value
        if entry.units == units or {entry.units, units} <= DIMENSIONLESS:
            return entry.value
        return entry.typed().to("dimensionless" if units in DIMENSIONLESS else units).magnitude

    @property
    def method(self) -> str | None:
        return self._plain("method")

    @property
    def method_reason(self) -> str | None:
        return self._plain("method_reason")

    @property
    def estimated_relative_error(self) -> float | None:
        """The declared relative error; seed 004's families report theirs as ``estimated_error`` (its declared
        error of the method, relative), which is the same quantity."""
        value = self._plain("estimated_relative_error")
        return self._plain("estimated_error") if value is None else value

    def keys(self) -> list[str]:
        return list(self._entries)

    def __getitem__(self, key):
        """A value: a pint Quantity where it has units, else the plain value."""
        return self.values[key]

    def __contains__(self, key) -> bool:
        return key in self._entries

    # --- what a family adds after the fact ------------------------------------------------------------------

    def add(self, key: str, value, units: str | None = None, label: str = "", also=()) -> "Result":
        """Add a value (SI, in ``units``; None for a plain value)."""
        self._entries[key] = Entry(key, value, units, label or key.replace("_", " "), tuple(also))
        return self

    def set(self, key: str, value) -> "Result":
        """Replace a value (its units and label stay)."""
        if key not in self._entries:
            raise KeyError(key)
        self._entries[key] = replace(self._entries[key], value=value)
        return self

    def note(self, text: str) -> "Result":
        self.notes.append(text)
        return self

    # --- derived: the report, the Dataset --------------------------------------------------------------------

    def report(self) -> Report:
        """The text and JSON report the CLI prints, derived from the values (a new Report each call)."""
        report = Report(self.title, notes=list(self.notes), sections=dict(self._sections))
        report.items = [Item(e.key, e.value, e.units, e.label, e.also, e.error, e.in_text)
                        for e in self._entries.values()]
        return report

    @property
    def summary(self) -> Report:
        """The report (an older name of :meth:`report`)."""
        return self.report()

    def to_xarray(self):
        """The result as an xarray Dataset, the schema the CLI writes: a simulation's time series, or else every
        number as a 0-d variable with its ``units`` (CF: "1" for a number) and every 95 % range beside it on a
        ``quantile`` dimension (its value's ``ancillary_variables``); the method and its declared error as
        attributes."""
        import xarray as xr  # heavy: imported where used

        variables, ranges = {}, {}
        for entry in (self._entries.values() if self.series is None else ()):  # a run's time series is its data
            if entry.is_range:  # the 2.5 and 97.5 % quantiles, beside the value it qualifies
                ranges[entry.key] = (("quantile",), [float(v) for v in entry.value],
                                     {"long_name": entry.label, "units": entry.units or "1"})
            elif entry.is_number:
                variables[entry.key] = ((), float(entry.value),
                                        {"long_name": entry.label, "units": entry.units or "1"})
            elif entry.is_pair:  # a low and a high on their own dimension
                variables[entry.key] = (("bound",), [math.inf if v is None else float(v) for v in entry.value],
                                        {"long_name": entry.label, "units": entry.units})
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
            "title": self.title, "faultslip_family": self.family, "method": self.method,
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
        printer.text(self.report().to_text())

    def __str__(self) -> str:
        return self.report().to_text()

    def __repr__(self) -> str:
        return f"<faultslip Result of {self.family}: {self.title}>"


class ReportedValues:
    """Result-style access for what a fit returns (a report and more, not a :class:`Result`): ``fit["a"]`` is a
    pint Quantity where it has units, ``fit.keys()`` every reported name, ``fit.as_result()`` the Result itself,
    so that a fit reads as a run does."""

    def as_result(self) -> Result:
        """The reported values as a :class:`Result`."""
        raise NotImplementedError

    def keys(self) -> list[str]:
        return self.as_result().keys()

    def __getitem__(self, key):
        """A reported value: a pint Quantity where it has units, else the plain value."""
        return self.as_result()[key]

    def __contains__(self, key) -> bool:
        return key in self.as_result()


def judge_tolerance(result: Result, tolerance) -> Result:
    """Say whether ``result`` meets the ``tolerance`` a run was asked for, for every family alike (``meets_tolerance``).

    A run asked for a relative error its declared error does not meet (a method's limit, a model error no richer
    rung removes, an unsettled sequence, a statistic of too few events), or that declares no bound at all, says so
    in a note and a warning, naming the method and its declared error: the answer is never handed over as if it
    met the tolerance. Without a tolerance the one that chose the method (``result.tolerance``: the scene's or the
    family's default) is judged; where none chose it, nothing is."""
    if tolerance is None:
        tolerance = getattr(result, "tolerance", None)
    if tolerance is None:
        return result
    error = result.estimated_relative_error
    bounded = isinstance(error, (int, float)) and not isinstance(error, bool) and math.isfinite(error)
    met = bounded and error <= float(tolerance)
    result.add("meets_tolerance", bool(met), label=f"the declared error meets the tolerance {float(tolerance):g}")
    if not met:
        said = f"declares a relative error of {error:.2g}" if bounded else "declares no bound on its error"
        sentence = (f"the answer does not meet the tolerance {float(tolerance):g}: {result.method or result.family} "
                    f"{said} (method_reason says why it was chosen; 'faultslip methods' lists each method's error)")
        result.note(sentence)
        warnings.warn(sentence, stacklevel=3)
    return result


def with_draws(dataset, kind: str, names, values):
    """``dataset`` with a fit's draws (bootstrap resamples or posterior samples, natural scale, SI) as the variable
    ``kind`` on (``kind``_draw, ``kind``_parameter), the parameters named on their coordinate; unchanged without
    draws."""
    import xarray as xr  # heavy: imported where used

    draws = xr.DataArray(values if values is not None else [[]], dims=(f"{kind}_draw", f"{kind}_parameter"))
    if draws.size == 0:
        return dataset
    draws = draws.astype(float).assign_coords({f"{kind}_parameter": [str(name) for name in names]})
    draws.attrs.update({"long_name": f"{kind} draws, natural scale (SI)", "units": "1"})
    return dataset.assign({kind: draws})

