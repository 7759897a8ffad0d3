"""The one slider calibrated against the 2-D fault in plane strain on dipping faults (faultslip.fault.dip_slider,
benchmarks/dip_slider_calibration.py)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import load_benchmark

import faultslip
from faultslip.fault import dip_slider, ladder
from faultslip.models.fault_2d.scene import read_fault_2d_scene

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "configs"
RESULTS = ROOT / "benchmarks" / "results"
BP3 = CONFIGS / "seas_bp3_thrust60.toml"


def test_the_shipped_calibration_is_the_fit_of_the_measured_faults():
    """Provenance of data/dip_slider_calibration.json: refitted here from the measured faults' saved plane-strain
    answers (benchmarks/results/dip_model_error.json) and the blocks the library derives from their scenes now,
    it is the shipped table, coefficient for coefficient."""
    bench = load_benchmark("dip_slider_calibration")
    results = json.loads((RESULTS / "dip_model_error.json").read_text(encoding="utf-8"))
    rows = [row for row in results["rows"]
            if not (row["set"] == "grid" and row["dip"] == 90.0 and row["sense"] == "normal")]
    base = read_fault_2d_scene(BP3)
    faults = [bench.block_of(base, row) for row in rows]
    shipped = dip_slider.load_table()
    assert shipped["window"] == bench.chosen_window(faults) and shipped["min_neighbours"] == bench.MIN_NEIGHBOURS
    refit = dip_slider.fit(faults, shipped["window"], shipped["min_neighbours"])
    for quantity in dip_slider.QUANTITIES:
        assert refit[quantity]["coefficients"] == pytest.approx(shipped[quantity]["coefficients"], rel=1e-9, abs=1e-12)
        assert refit[quantity]["residual_sd"] == pytest.approx(shipped[quantity]["residual_sd"], rel=1e-9)
        assert np.allclose(refit[quantity]["residual_points"], shipped[quantity]["residual_points"], rtol=1e-9)
        assert refit[quantity]["faults"] == len(rows) >= 150
    assert refit["box"].keys() == shipped["box"].keys() and refit["senses"] == ["normal", "thrust"]
    for name, bounds in refit["box"].items():
        assert bounds == pytest.approx(shipped["box"][name], rel=1e-12), name


def test_the_ranges_hold_on_the_dipping_faults_the_fit_never_saw():
    """benchmarks/results/dip_slider_calibration.json: on the held-out dipping faults (never part of the fit) the
    recurrence's and mean slip's 95 % ranges hold the plane-strain answer on at least 95 % of the faults where
    they are declared, far narrower than the composed range they replace, and the surface slip's composed range
    on all where it is declared. With the fresh draws run since (dip_model_error.py --fresh, read against this
    table as shipped: its rows are what the library answers now), the unseen faults together hold at 95 % too.
    Where a fresh fault's plane-strain run settled, its misses are no more than a 95 % range allows (binomial, 1 %
    level); most misses are where it did not settle (docs/dipping_faults.md). Draws 4313 and 4315's misses had
    all been unsettled faults until 4315 put two settled ones 0.02 % and 1 % outside their ranges."""
    bench = load_benchmark("dip_model_error")
    result = json.loads((RESULTS / "dip_slider_calibration.json").read_text(encoding="utf-8"))
    summary = result["summary"]
    for quantity in dip_slider.QUANTITIES:
        side = summary[quantity]
        assert side["declared"] >= 50 and side["within"] >= 0.95 * side["declared"], quantity
        assert side["mean_half_width"] < 0.5 * summary["composed"]["mean_half_width"]
    assert summary["surface_slip"]["within"] == summary["surface_slip"]["declared"] >= 10
    base = read_fault_2d_scene(BP3)
    fresh = [row for path in sorted(RESULTS.glob("dip_model_error_fresh_*.json"))
             for row in json.loads(path.read_text(encoding="utf-8"))["held_out"]
             if row["one_slider"].get("calibrated_against") == "the 2-D fault in plane strain"]
    assert len(fresh) >= 30
    for row in result["held_out"][::6] + fresh[::4]:  # a sample: each is one block's cycles
        now = bench.slider_side(base, row)
        for key, value in row["one_slider"].items():
            if key.endswith("half_width"):
                continue
            assert now[key] == (pytest.approx(value, rel=1e-9) if isinstance(value, (float, list)) else value), key
    unseen = [row["one_slider"] for row in result["held_out"]] + [row["one_slider"] for row in fresh]
    for quantity in dip_slider.QUANTITIES:
        ranged = [side[f"{quantity}_holds"] for side in unseen if side.get(f"{quantity}_holds") is not None]
        assert sum(ranged) >= 0.95 * len(ranged) and len(ranged) >= 90, quantity
    from scipy import stats

    for quantity in ("recurrence", "mean_slip"):
        holds = [row["one_slider"][f"{quantity}_holds"] for row in fresh if row["plane_strain"]["settled"]
                 and row["one_slider"].get(f"{quantity}_holds") is not None]
        assert len(holds) >= 50 and holds.count(False) <= stats.binom.ppf(0.99, len(holds), 0.05), quantity


def test_bp3s_one_slider_is_calibrated_against_plane_strain_whatever_the_dip_error(monkeypatch):
    """Inside the calibration's box (BP3's own fault at 60 degrees) the recurrence's and mean slip's ranges are the
    direct calibration's prediction intervals: they do not read the antiplane rung's dip error (a declared 1.2,
    which leaves a composed range no upper end, changes neither), and the report names the rung they were fitted
    to. The surface slip's range is the composed one, so that error takes it away."""
    scene = read_fault_2d_scene(BP3)
    before = faultslip.run(scene, method="one_slider")
    monkeypatch.setattr(ladder.dip_error, "declared", lambda dip, width_over_nucleation: 1.2)
    after = faultslip.run(scene, method="one_slider")
    assert before.values["calibrated_against"] == "the 2-D fault in plane strain"
    for key in ("recurrence_range", "mean_slip_per_event_range"):
        assert [v.to("s" if "recurrence" in key else "m").magnitude for v in after.values[key]] == pytest.approx(
            [v.to("s" if "recurrence" in key else "m").magnitude for v in before.values[key]], rel=1e-12)
    assert before.values["slip_per_event_range"] is not None and after.values["slip_per_event_range"] is None
    fault = scene.fault.description()
    raw, group = ladder.block_answer(fault)
    band = dip_slider.predict("recurrence", raw["recurrence"], group, fault.dip, fault.sense)
    low, high = (float(v.to("s").magnitude) for v in before.values["recurrence_range"])
    assert (low, high) == pytest.approx((band["low"], band["high"]), rel=1e-12)
    assert after.estimated_relative_error == pytest.approx(ladder.declared_error(fault), rel=1e-12)
    assert after.estimated_relative_error < 0.5 < before.estimated_relative_error  # the composed surface range


def test_outside_the_box_the_composed_range_stands_and_the_report_says_why():
    """A dip below the measured (20 degrees) or a profile not BP3's (b = 0.0165) lies outside the
    calibration: the one slider falls back to the antiplane calibration widened by the dip error, and a note
    names the group that left the box."""
    base = read_fault_2d_scene(BP3)
    for scene, group_name in ((base.with_values(dip=20.0), "dip = 20"),
                              (base.with_values(b=0.0165), "a_over_b")):
        fault = scene.fault.description()
        assert dip_slider.outside(ladder.groups(fault), fault.dip, fault.sense)
        result = faultslip.run(scene, method="one_slider")
        assert result.values.get("calibrated_against") in (None, "the 2-D fault in antiplane strain")
        assert any("do not span this one" in note and group_name in note for note in result.notes), result.notes


@settings(max_examples=8, deadline=None)
@given(critical_slip=st.floats(0.007, 0.020), depth=st.floats(12.5e3, 15.5e3))
def test_a_vertical_fault_is_one_fault_whichever_its_sense(critical_slip, depth):
    """Dip slip on a vertical fault leaves its normal stress unchanged, so its thrust and normal senses are one
    fault: the correction's sense term (s cos(dip)) vanishes there and both read the same answer and range."""
    base = read_fault_2d_scene(BP3).with_values(dip=90.0, critical_slip=critical_slip, seismogenic_depth=depth)
    fault = base.fault.description()
    group = ladder.groups(fault)
    if dip_slider.outside(group, 90.0, "thrust"):
        return
    thrust = dip_slider.predict("recurrence", 1.0, group, 90.0, "thrust")
    normal = dip_slider.predict("recurrence", 1.0, group, 90.0, "normal")
    for key in ("value", "low", "high"):
        assert thrust[key] == pytest.approx(normal[key], rel=1e-12)


@settings(max_examples=20, deadline=None)
@given(width_over_nucleation=st.floats(0.9, 4.1), dip=st.floats(30.0, 90.0),
       sense=st.sampled_from(["thrust", "normal"]))
def test_the_range_is_a_prediction_interval_about_the_corrected_block(width_over_nucleation, dip, sense):
    """Each range is symmetric in ln about the corrected value, at least t s of the calibration faults near the
    fault's W / h* (leverage only adds), and the value is the block times exp(x . beta); where too few were
    measured near, there is no range."""
    from scipy import stats

    table = dip_slider.load_table()
    group = {"width_over_nucleation": width_over_nucleation}
    for quantity in dip_slider.QUANTITIES:
        band = dip_slider.predict(quantity, 2.0, group, dip, sense)
        near = np.asarray(dip_slider.neighbourhood(quantity, width_over_nucleation))
        if near.size < table["min_neighbours"]:
            assert band is None
            continue
        x = dip_slider.features(group, dip, sense)
        assert band["value"] == pytest.approx(2.0 * math.exp(float(x @ np.asarray(table[quantity]["coefficients"]))))
        assert math.log(band["high"] / band["value"]) == pytest.approx(math.log(band["value"] / band["low"]))
        local = stats.t.ppf(0.975, near.size - 1) * math.sqrt(np.mean(near ** 2))
        assert math.log1p(band["half_width"]) >= local * (1 - 1e-12)
