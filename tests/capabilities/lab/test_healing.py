"""Slide-hold-slide healing (issue 46, item 3): the aging law's log-time healing by hand, the slip law's lack of it,
the rate's interval, refusals, and the fit's report.

Provenance: for the aging law on a stiff machine the state grows as theta_ss + t_h during a hold, so the peak on
reloading is Delta mu = b ln(1 + t_h V / D_c) (Beeler, Tullis & Weeks 1994), whose slope per decade tends to b ln 10.
"""

import math

import numpy as np
import pytest

from faultslip.dynamics.rate_state.slider import LoadHistory
from faultslip.errors import InputError
from faultslip.friction.rate_state import RateStateLaw
from faultslip.lab.healing import healing
from faultslip.lab.rate_state_fit import synthetic_step_record

LAW = RateStateLaw(a=0.006, b=0.009, critical_slip=10e-6, mu0=0.6, reference_speed=1e-6)
HOLDS = [100.0, 300.0, 1000.0, 3000.0, 10000.0]
HISTORY = LoadHistory.slide_hold_slide(1e-6, 100.0, HOLDS)
STIFF = 1e6  # friction per metre: a stiff machine, little slip in a hold


def test_the_aging_law_heals_as_b_ln_of_the_hold_time():
    result = healing(synthetic_step_record(LAW, STIFF, HISTORY, 40001))
    np.testing.assert_allclose(result.hold_time, HOLDS)
    by_hand = LAW.b * np.log1p(np.array(HOLDS) * 1e-6 / LAW.critical_slip)
    np.testing.assert_allclose(result.healing, by_hand, rtol=0.02)  # the peak, sampled every 0.3 s
    assert 0.95 * LAW.b * math.log(10) < result.rate < LAW.b * math.log(10)
    low, high = result.rate_interval
    assert low < result.rate < high and np.all(result.relaxation >= 0)
    dataset = result.to_dataset()
    assert dataset["hold_time"].attrs["units"] == "s" and dataset.attrs["healing_rate_per_decade"] == result.rate


def test_the_slip_law_barely_heals_in_stationary_contact():
    aging = healing(synthetic_step_record(LAW, STIFF, HISTORY, 40001))
    slip = healing(synthetic_step_record(LAW.with_evolution("slip"), STIFF, HISTORY, 40001))
    assert slip.rate < 0.05 * aging.rate


def test_a_noisy_records_interval_holds_the_noiseless_rate():
    truth = healing(synthetic_step_record(LAW, STIFF, HISTORY, 40001)).rate
    covered = sum(low <= truth <= high for low, high in
                  (healing(synthetic_step_record(LAW, STIFF, HISTORY, 40001, noise=2e-4, seed=seed)).rate_interval
                   for seed in range(10)))
    assert covered >= 8


def test_refusals_and_what_too_few_holds_give():
    steps = synthetic_step_record(LAW, 1e4, LoadHistory.velocity_steps([(0.0, 1e-6), (20.0, 1e-5)], 40.0), 401)
    with pytest.raises(InputError, match="no hold between two slides"):
        healing(steps)
    two = healing(synthetic_step_record(LAW, STIFF, LoadHistory.slide_hold_slide(1e-6, 100.0, [100.0, 1000.0]), 4001))
    assert math.isfinite(two.rate) and not math.isfinite(two.rate_error) and "without an interval" in two.notes[0]
    same = healing(synthetic_step_record(LAW, STIFF, LoadHistory.slide_hold_slide(1e-6, 100.0, [100.0, 100.0]), 4001))
    assert math.isnan(same.rate) and "as long as the others" in same.notes[0]


def test_the_fit_reports_the_healing_of_a_slide_hold_slide_record(cli, tmp_path):
    record = synthetic_step_record(LAW, 1e5, LoadHistory.slide_hold_slide(1e-6, 60.0, [30.0, 100.0, 300.0]), 3001,
                                   noise=1e-4, seed=1)
    path = tmp_path / "shs.csv"
    displacement = record.history.displacement(record.time)
    path.write_text("time (s),friction,load_point_displacement (m)\n" + "".join(
        f"{t:.17g},{m:.17g},{x:.17g}\n" for t, m, x in zip(record.time, record.friction, displacement)),
        encoding="utf-8")
    out = cli("fit", "--law", "rate-state", path, "--stiffness", "0.1 1/um", "--bootstrap", "0", "--json")
    assert out.code == 0, out.err
    assert out.json["hold_1"]["hold_time"]["value"] == pytest.approx(30.0, abs=0.5)
    assert out.json["healing_rate"]["value"] > 0 and out.json["healing_rate_95"]["units"] == "1"


def test_the_steady_state_dependence_is_a_minus_b_by_hand():
    from faultslip.lab.healing import steady_state_dependence

    history = LoadHistory.velocity_steps([(0.0, 1e-6), (60.0, 1e-5), (120.0, 1e-4), (180.0, 1e-5)], 240.0)
    rows = steady_state_dependence(synthetic_step_record(LAW, 1e5, history, 24001))
    assert [round(row.speed_after / row.speed_before, 9) for row in rows] == [10.0, 10.0, 0.1]
    for row in rows:
        assert row.a_minus_b == pytest.approx(LAW.a - LAW.b, rel=1e-3)
