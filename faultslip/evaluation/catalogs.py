"""Predicted against observed recurrence and magnitude (``faultslip catalog``).

The events on a fault are those within ``max_distance`` of its trace (great circles), above a
magnitude and inside a time window. Their intervals are summarised and fitted with the lognormal and
Brownian-passage-time renewal models (:mod:`faultslip.fault.recurrence`); the scene's prediction
(the seed law, or rate-and-state friction where the scene has it) is set beside them as ratios and as
the percentile of the predicted recurrence within each fitted model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from faultslip.errors import InputError
from faultslip.fault import recurrence
from faultslip.fault.scene import Scene, estimate_scene_rate_state
from faultslip.io.catalogs import Catalog
from faultslip.io.geo import distance_to_trace
from faultslip.io.report import Report
from faultslip.units import to_si_scalar
from faultslip.datasets import ToXarray

YEAR = recurrence.SECONDS_PER_YEAR


@dataclass
class Prediction:
    law: str  # "seed" or "rate_state"
    recurrence: float | None  # s (None: no stick-slip)
    slip_per_event: float | None  # m
    magnitude: float | None


@dataclass
class CatalogComparison(ToXarray):
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'distances': 'm', 'elapsed': 's', 'horizon': 's'}
    DIMENSIONS = {'distances': 'event'}
    selected: Catalog
    distances: np.ndarray  # m, of the selected events
    criteria: dict
    prediction: Prediction
    summary: dict | None = None
    fits: dict = field(default_factory=dict)  # model -> RenewalFit
    elapsed: float | None = None  # s since the last event at as_of
    horizon: float | None = None
    as_of: np.datetime64 | None = None
    notes: list = field(default_factory=list)
    mainshocks: Catalog | None = None  # the selection declustered, when it held clusters

    def report(self, title: str = "faultslip catalog comparison") -> Report:
        r = Report(title)
        r.add("events", len(self.selected), label="events selected")
        if self.mainshocks is not None:
            r.add("mainshocks", len(self.mainshocks), label="mainshocks after declustering (what the fits use)")
        for key, value in self.criteria.items():
            r.add(key, value)
        rows = [{"time": str(t), "magnitude": float(m), "name": n,
                 "distance": {"value": None if math.isnan(d) else float(d), "units": "m"}}
                for t, m, n, d in zip(self.selected.time, self.selected.magnitude, self.selected.name, self.distances)]
        r.add("event_list", {"events": rows, "summary": ", ".join(f"{str(t)[:10]} M{m:g}" for t, m in
                                                                 zip(self.selected.time, self.selected.magnitude))},
              label="events")
        r.section("Observed")
        if self.summary is not None:
            r.add("observed_mean_interval", self.summary["mean"], "s", also=("yr",), label="mean interval")
            r.add("observed_cv", self.summary["cv"], label="coefficient of variation (ddof 1)")
            r.add("observed_intervals", self.summary["count"], label="intervals")
        r.add("observed_max_magnitude", float(self.selected.magnitude.max()), label="largest magnitude")
        for model, fitted in self.fits.items():
            r.add(f"{model}_mean", fitted.mean, "s", also=("yr",), label=f"{model}: mean recurrence (ML)")
            r.add(f"{model}_mean_95", _bounds(fitted.mean_95), "s", also=("yr",), label=f"{model}: mean, 95 % range")
            r.add(f"{model}_aperiodicity", fitted.aperiodicity, label=f"{model}: aperiodicity")
            r.add(f"{model}_aperiodicity_95", _bounds(fitted.aperiodicity_95), label=f"{model}: aperiodicity, 95 %")
            if not all(math.isfinite(v) for v in (*fitted.mean_95, *fitted.aperiodicity_95)):
                r.note(f"{model}: a 95 % range is unbounded above (null): the intervals are too few to bound it")
            if fitted.probability is not None:
                r.add(f"{model}_probability", fitted.probability,
                      label=f"{model}: P(event in {self.horizon / YEAR:g} yr | {self.elapsed / YEAR:.1f} yr elapsed)")
                if fitted.probability_95 is not None:
                    r.add(f"{model}_probability_95", _bounds(fitted.probability_95), label=f"{model}: probability, 95 %")
        p = self.prediction
        r.section(f"Predicted ({'rate-and-state friction' if p.law == 'rate_state' else 'seed law'})")
        if p.recurrence is None:
            r.add("predicted_regime", "no stick-slip: the model predicts no characteristic events")
        else:
            r.add("predicted_recurrence", p.recurrence, "s", also=("yr",), label="predicted recurrence")
            r.add("predicted_slip_per_event", p.slip_per_event, "m", label="predicted slip per event")
            if self.summary is not None:
                r.add("recurrence_ratio", p.recurrence / self.summary["mean"], label="predicted / observed mean interval")
            for model, fitted in self.fits.items():
                law = recurrence.distribution(model, fitted.mean, fitted.aperiodicity)
                r.add(f"{model}_percentile", float(law.cdf(p.recurrence)),
                      label=f"{model}: percentile of the prediction in the fitted model")
        if p.magnitude is not None:
            r.add("predicted_magnitude", p.magnitude, label="predicted Mw")
            r.add("magnitude_difference", p.magnitude - float(self.selected.magnitude.max()),
                  label="predicted Mw - largest observed")
        for note in self.notes:
            r.note(note)
        return r


def select(catalog: Catalog, trace=None, max_distance: float = 25e3, min_magnitude: float | None = None,
           since=None, until=None, max_magnitude: float | None = None):
    """(the events on the fault, their distances to the trace in m; NaN without a trace)."""
    if not max_distance > 0:
        raise InputError(f"max_distance must be positive, got {max_distance:g} m")
    keep = np.ones(len(catalog), dtype=bool)
    distances = np.full(len(catalog), math.nan)
    if trace is not None:
        distances = distance_to_trace(catalog.longitude, catalog.latitude, trace)
        keep &= distances <= max_distance
    if min_magnitude is not None:
        keep &= catalog.magnitude >= min_magnitude
    if max_magnitude is not None:
        keep &= catalog.magnitude <= max_magnitude
    if since is not None:
        keep &= catalog.time >= since
    if until is not None:
        keep &= catalog.time <= until
    return catalog.subset(keep), distances[keep]


def predict(scene: Scene) -> Prediction:
    """The scene's recurrence, slip and Mw: rate-and-state friction where the scene has it, else the seed law."""
    if scene.kind != "fault":
        raise InputError(f"{scene.name} is a {scene.kind} scene; the catalog comparison needs a fault scene")
    if scene.rate_state:
        estimate = estimate_scene_rate_state(scene)
        cycles = estimate.cycles
        if cycles is None:
            return Prediction("rate_state", None, None, None)
        return Prediction("rate_state", float(cycles.recurrence), float(cycles.slip_per_event.mean()), estimate.magnitude)
    estimate = scene.fault().estimate()
    if estimate.regime != "stick_slip":
        return Prediction("seed", None, None, None)
    return Prediction("seed", float(estimate.recurrence_period), float(estimate.slip_per_event),
                      estimate.moment_magnitude)


#: Intervals shorter than this fraction of the mean are clustering (fore- and aftershocks), not renewal.
CLUSTER_FRACTION = 0.01


def decluster(selected: Catalog, fraction: float = CLUSTER_FRACTION) -> tuple[Catalog, list]:
    """The mainshocks of ``selected``: while the shortest interval is under ``fraction`` of the mean
    interval, its two events are one cluster, represented by the larger (the earlier on a tie); the mean
    is recomputed after each merge. Returns (declustered catalog, [(removed name or time, kept), ...])."""
    keep = np.ones(len(selected), bool)
    removed = []
    seconds, magnitude = selected.seconds(), np.asarray(selected.magnitude, float)
    while keep.sum() >= 3:
        index = np.flatnonzero(keep)
        gaps = np.diff(seconds[index])
        shortest = int(np.argmin(gaps))
        if gaps[shortest] >= fraction * gaps.mean():
            break
        first, second = index[shortest], index[shortest + 1]
        weaker = second if np.nan_to_num(magnitude[first], nan=-9) >= np.nan_to_num(magnitude[second], nan=-9) \
            else first
        kept = first if weaker == second else second
        keep[weaker] = False
        label = lambda i: selected.name[i] or str(selected.time[i])[:19]  # noqa: E731
        removed.append((label(weaker), label(kept), float(gaps[shortest])))
    return selected.subset(keep), removed


def compare(catalog: Catalog, scene: Scene, trace=None, max_distance: float = 25e3, min_magnitude=None, since=None,
            until=None, as_of=None, horizon: float = 30 * YEAR, bootstrap: int = 1000, seed: int = 0,
            max_magnitude=None, cluster_fraction: float | None = CLUSTER_FRACTION) -> CatalogComparison:
    """Select the fault's events, fit their recurrence and set the scene's prediction beside them.

    ``max_distance`` and ``horizon`` take units ("25 km", "30 yr", a Quantity) or floats in metres and
    seconds. A renewal model describes mainshocks: intervals under ``cluster_fraction`` of the mean are
    declustered (:func:`decluster`, the rule and the removed events in the notes); ``None`` refuses such
    a selection instead.

    Parameters
    ----------
    catalog : Catalog
        :func:`read_catalog`'s catalog.
    scene : Scene
        The fault scene whose prediction is compared.
    trace : array_like, optional
        The fault trace ((lon, lat) in degrees); the scene's otherwise.
    max_distance : str, Quantity or float
        Events within this distance of the trace (m).
    min_magnitude, max_magnitude : float, optional
        The magnitudes kept.
    since, until, as_of : numpy.datetime64, optional
        The time window, and the date of the conditional probability.
    horizon : str, Quantity or float
        The probability's horizon (s).
    bootstrap : int
        Parametric bootstrap samples of the 95 % ranges.
    seed : int
        The bootstrap's seed.
    cluster_fraction : float or None
        Intervals under this fraction of the mean are declustered (None: refused).

    Returns
    -------
    CatalogComparison
        The selected events, the renewal fits with their 95 % ranges, the prediction beside them, ``report()``.
    """
    max_distance = to_si_scalar(max_distance, "length", "max_distance", default_unit="m")
    horizon = to_si_scalar(horizon, "time", "horizon", default_unit="s")
    if not horizon > 0:
        raise InputError("the probability horizon must be positive")
    selected, distances = select(catalog, trace, max_distance, min_magnitude, since, until, max_magnitude)
    if len(selected) == 0:
        raise InputError(f"no event of {catalog.path and catalog.path.split('/')[-1] or 'the catalog'} passes the "
                         "selection (distance to the trace, magnitude, time); widen --max-distance or lower "
                         "--min-magnitude")
    criteria = {"max_distance": f"{max_distance / 1e3:g} km" if trace is not None else "no trace: every location",
                "min_magnitude": min_magnitude if min_magnitude is not None else "none",
                "max_magnitude": max_magnitude if max_magnitude is not None else "none"}
    comparison = CatalogComparison(selected, distances, criteria, predict(scene), horizon=horizon,
                                   notes=list(catalog.notes))
    if len(selected) < 3:
        comparison.notes.append(f"{len(selected)} event(s): too few intervals for a renewal fit (3 events at least); "
                                "only magnitudes are compared")
        return comparison
    gaps = recurrence.intervals(selected.seconds())
    if gaps.min() < (cluster_fraction or CLUSTER_FRACTION) * gaps.mean():
        # a renewal model describes mainshocks, not their fore- or aftershocks
        if cluster_fraction is None:
            raise InputError(f"the shortest interval, {gaps.min() / 86400:.3g} days, is under "
                             f"{CLUSTER_FRACTION:.0%} of the mean: the selection holds clustered events (foreshocks "
                             "or aftershocks) that a renewal model does not describe; decluster it (the default) or "
                             "narrow it with --max-magnitude or a time window")
        selected, removed = decluster(selected, cluster_fraction)
        comparison.mainshocks = selected
        comparison.notes.append(
            f"declustered: while the shortest interval was under {cluster_fraction:.3g} of the mean interval, its "
            f"smaller event was taken as a fore- or aftershock of the larger and removed ({len(removed)} removed: " +
            "; ".join(f"{weak} {gap / 86400:.3g} days from {strong}" for weak, strong, gap in removed) + ")")
        if len(selected) < 3:
            comparison.notes.append(f"{len(selected)} mainshock(s) after declustering: too few intervals for a "
                                    "renewal fit; only magnitudes are compared")
            return comparison
        gaps = recurrence.intervals(selected.seconds())
    comparison.summary = recurrence.summary(gaps)
    last = selected.seconds()[-1]
    if as_of is None:
        as_of = np.datetime64("now", "ms")
    elapsed = float(np.datetime64(as_of, "ms").astype(np.int64) / 1e3 - last)
    if elapsed < 0:
        raise InputError("--as-of lies before the last selected event")
    comparison.as_of, comparison.elapsed = np.datetime64(as_of, "ms"), elapsed
    for index, model in enumerate(recurrence.MODELS):
        comparison.fits[model] = recurrence.fit(model, gaps, bootstrap=bootstrap, seed=seed + index, elapsed=elapsed,
                                                horizon=horizon)
        if comparison.fits[model].widened:
            comparison.notes.append(f"{model}: the 95 % range of its {', '.join(comparison.fits[model].widened)}"
                                    " is widened to contain the estimate (the resampled estimates are skewed past it)")
    comparison.notes.append(f"probabilities as of {str(comparison.as_of)[:10]} ({elapsed / YEAR:.1f} yr after the last "
                            f"event), 95 % ranges from {bootstrap} draws of the generalized pivotal quantities (seed {seed})")
    if len(selected) < 10:
        comparison.notes.append(f"{comparison.summary['count']} intervals: the renewal parameters are loosely "
                                "constrained; read the 95 % ranges")
    return comparison


def _bounds(pair) -> list:
    """A 95 % range for a report: an unbounded end (too few intervals for the pivot to bound it) is None."""
    return [float(v) if math.isfinite(v) else None for v in pair]
