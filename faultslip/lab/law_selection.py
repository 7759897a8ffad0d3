"""Which state-evolution law a velocity-step record supports: aging, slip, or two state variables.

Each candidate is fitted by least squares (:func:`faultslip.lab.rate_state_fit.fit_velocity_steps`) and scored
by the Bayesian information criterion for Gaussian errors of unknown variance (Schwarz 1978):

    BIC = n ln(SSR / n) + p ln n,

n the record's points, p the law's parameters (mu0, a, b, D_c; a second state adds b2 and D_c2; a free
stiffness adds k, a fitted trend c). The lowest BIC wins.

A real rig's residuals are not independent: a fast logger (p655: 1 ms) samples the same wander of the noise many
times, and n would count it as that many independent points, overstating every Delta BIC. So n is the effective
number of points of AR(1) residuals, n_eff = n (1 - rho) / (1 + rho), rho the lag-one autocorrelation of the
best-fitting candidate's residuals (clipped at 0; Bayley & Hammersley 1946, the variance of a mean of correlated
points): BIC = n_eff ln(SSR / n) + p ln n_eff. Independent noise leaves n_eff = n to within rho's scatter. Delta BIC approximates 2 ln of the Bayes factor against the winner, read on
Kass & Raftery's (1995, JASA 90, 773-795, §3.2) scale: 0-2 not worth more than a bare mention, 2-6 positive, 6-10
strong, above 10 very strong. The Schwarz weights exp(-Delta/2) / sum say the same as probabilities among the
candidates (equal prior odds). A candidate whose fit fails is listed with the reason and takes no weight.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from faultslip.io.progress import counted
from faultslip.errors import FaultslipError, InputError
from faultslip.lab.rate_state_fit import fit_velocity_steps, lag_one_autocorrelation
from faultslip.datasets import ToXarray
from faultslip.units import takes_units

#: candidate -> (evolution, two_state)
LAWS = {"aging": ("aging", False), "slip": ("slip", False), "aging_two_state": ("aging", True),
        "slip_two_state": ("slip", True)}
DEFAULT_CANDIDATES = ("aging", "slip", "aging_two_state")
CRITERION = ("BIC = n_eff ln(SSR/n) + p ln n_eff, n_eff = n (1 - rho) / (1 + rho) (Schwarz 1978; rho the residuals' "
             "lag-one autocorrelation)")
#: Kass & Raftery (1995): the lower edge of each category of Delta BIC (about 2 ln B)
EVIDENCE = ((10.0, "very strong"), (6.0, "strong"), (2.0, "positive"), (0.0, "not worth more than a bare mention"))


def evidence(delta: float) -> str:
    """Kass & Raftery's (1995) words for a Delta BIC (about 2 ln of the Bayes factor)."""
    for edge, words in EVIDENCE:
        if delta >= edge:
            return words
    return EVIDENCE[-1][1]


@dataclass
class LawSelection(ToXarray):
    """Each candidate's fit and score, and the verdict."""

    rows: list  # dicts: law, parameters, ssr, bic, delta, weight, fit (or error)
    points: int
    notes: list = field(default_factory=list)
    autocorrelation: float = 0.0  # the best fit's residuals' lag-one autocorrelation
    effective_points: float = 0.0  # the n the criterion counts

    @property
    def chosen(self) -> str:
        return min((row for row in self.rows if "bic" in row), key=lambda row: row["bic"])["law"]

    @property
    def runner_up(self) -> dict | None:
        scored = sorted((row for row in self.rows if "bic" in row), key=lambda row: row["bic"])
        return scored[1] if len(scored) > 1 else None

    def verdict(self) -> str:
        second = self.runner_up
        if second is None:
            return f"only the {self.chosen} law could be fitted"
        return (f"the record supports the {self.chosen} law over the {second['law']} law by Delta BIC = "
                f"{second['delta']:.3g} ({evidence(second['delta'])} evidence, Kass & Raftery 1995)")

    def to_dataset(self):
        """The candidates as an xarray Dataset on dimension ``law`` (BIC, Delta BIC, Schwarz weight, parameters), the
        verdict in its attributes; a candidate that could not be fitted has NaN."""
        import xarray as xr  # heavy: imported where used

        laws = [row["law"] for row in self.rows]
        column = lambda key: np.array([row.get(key, np.nan) for row in self.rows], dtype=float)  # noqa: E731
        return xr.Dataset(
            {"bic": ("law", column("bic"), {"units": "1", "long_name": "Bayesian information criterion"}),
             "delta_bic": ("law", column("delta"), {"units": "1", "long_name": "BIC less the lowest (about 2 ln B)"}),
             "weight": ("law", column("weight"), {"units": "1", "long_name": "Schwarz weight"}),
             "parameters": ("law", column("parameters"), {"units": "1", "long_name": "parameters fitted"})},
            coords={"law": ("law", np.array(laws, dtype=str))},
            attrs={"chosen": self.chosen, "verdict": self.verdict(), "points": self.points,
                   "effective_points": self.effective_points, "residual_autocorrelation": self.autocorrelation,
                   "criterion": CRITERION})

    def to_dict(self) -> dict:
        return {"criterion": CRITERION, "points": self.points, "effective_points": self.effective_points,
                "residual_autocorrelation": self.autocorrelation,
                "chosen": self.chosen, "verdict": self.verdict(),
                "candidates": [{key: value for key, value in row.items() if key != "fit"} for row in self.rows],
                "notes": self.notes}


@takes_units(stiffness="inverse_length")
def select_law(record, stiffness, candidates=DEFAULT_CANDIDATES, stiffness_free: bool = False,
               trend: bool = False, progress=None) -> LawSelection:
    """Fit each candidate law to ``record`` and score it by BIC (see the module).

    Parameters
    ----------
    record : StepRecord
        A velocity-step record (friction against time).
    stiffness : float
        The machine stiffness as friction per slip (1/m); the start of a free one.
    candidates : sequence of str
        Among :data:`LAWS`: aging, slip, aging_two_state, slip_two_state.
    stiffness_free : bool
        Fit the stiffness in every candidate.
    trend : bool
        Fit a linear trend in the load point's displacement in every candidate.
    progress : bool or callable, optional
        Report the candidates fitted (True: a bar; the rest's expected time said after the first).

    Returns
    -------
    LawSelection
        Each candidate's parameters, SSR, BIC, Delta BIC and Schwarz weight, and the verdict.
    """
    unknown = [name for name in candidates if name not in LAWS]
    if unknown or len(set(candidates)) < 2:
        raise InputError(f"law selection compares two or more of {', '.join(LAWS)}, got {', '.join(candidates)}")
    rows, elapsed = [], None
    step = counted(progress, "law selection", len(candidates), "law", "fitting each candidate law")
    for done, name in enumerate(candidates):
        if step is not None:
            step(done, elapsed if done == 1 else None)
        began = time.process_time()
        evolution, two_state = LAWS[name]
        try:
            fit = fit_velocity_steps(record, stiffness, evolution=evolution, two_state=two_state,
                                     stiffness_free=stiffness_free, trend=trend)
        except FaultslipError as error:
            rows.append({"law": name, "error": str(error)})
            elapsed = time.process_time() - began
            continue
        elapsed = time.process_time() - began
        n = fit.points
        rows.append({"law": name, "parameters": len(fit.parameters), "ssr": fit.residual_rms ** 2 * n,
                     "values": dict(fit.parameters), "fit": fit, "notes": list(fit.notes)})
    if step is not None:
        step(len(candidates))
    scored = [row for row in rows if "ssr" in row]
    if not scored:
        raise InputError("no candidate law could be fitted to the record: " + "; ".join(row["error"] for row in rows))
    record_points = int(scored[0]["fit"].points)
    n = record_points
    residuals = min(scored, key=lambda row: row["ssr"])["fit"].residuals
    rho = lag_one_autocorrelation(residuals)
    effective = max(n * (1.0 - rho) / (1.0 + rho), float(max(row["parameters"] for row in scored) + 2))
    for row in scored:
        row["bic"] = effective * math.log(row["ssr"] / n) + row["parameters"] * math.log(effective)
    best = min(row["bic"] for row in scored)
    weights = np.array([math.exp(-(row["bic"] - best) / 2) for row in scored])
    for row, weight in zip(scored, weights / weights.sum()):
        row["delta"] = row["bic"] - best
        row["weight"] = float(weight)
    notes = [f"the residuals' lag-one autocorrelation is {rho:.3g}: the criterion counts {effective:.4g} effective "
             f"points of the record's {record_points}"]
    return LawSelection(rows, int(record_points), notes, autocorrelation=rho, effective_points=effective)
