"""The ladder (issue 68): every rung reads one description of the fault; the one slider is derived from its
profile, corrected by the 2-D calibration, and its 95 % ranges hold the 2-D answer on faults held out of it."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import faultslip
from conftest import assert_clean_error, load_benchmark, modelled_seconds
from faultslip.errors import InputError
from faultslip.fault import ladder
from faultslip.models.fault_2d.scene import read_fault_2d_scene
from faultslip.units import to_si_scalar

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "configs"
HELD_OUT = ROOT / "benchmarks" / "results" / "ladder_held_out.json"
RESULTS = ROOT / "benchmarks" / "results"
YEAR = 365.25 * 86400.0


def _description(a, element_size=100.0, b=0.015):
    a = np.asarray(a, float)
    depth = (np.arange(a.size) + 0.5) * element_size
    full = np.full(a.size, 1.0)
    return ladder.FaultDescription(depth, a, full * b, full * 0.008, full * 50e6, element_size, 32.04e9, 3464.0, 1e-9)


def test_the_rupture_zone_is_the_widest_weakening_run():
    a = [0.02] * 3 + [0.01] * 4 + [0.02] * 2 + [0.01] * 10 + [0.025] * 5
    zone = ladder.rupture_zone(_description(a))
    assert (zone.start, zone.stop) == (9, 19)
    group = ladder.groups(_description(a))
    assert group["width"] == 1000.0
    assert group["burial"] == pytest.approx(0.9)  # 900 m of cap over 1 km
    assert group["strengthening_depth"] == pytest.approx(0.5)


def test_a_fault_that_only_creeps_is_refused():
    with pytest.raises(InputError, match="creeps"):
        ladder.rupture_zone(_description([0.02] * 10))


def test_bp1s_groups_follow_from_its_profile():
    """BP1: a < b to 16 km (a reaches b = 0.015 a third of the way up the 15-18 km ramp); h* and L_b from the
    zone's means (Rubin & Ampuero 2005)."""
    fault = read_fault_2d_scene(CONFIGS / "rsf_fault_bp1.toml").fault.description()
    group = ladder.groups(fault)
    assert group["width"] == pytest.approx(16e3)
    a = 0.010 * 150 / 160 + np.mean(0.010 + 0.015 * (np.arange(10) + 0.5) * 100 / 3e3) * 10 / 160
    assert group["a"] == pytest.approx(a, rel=1e-12)
    nucleation = math.pi / 2 * fault.shear_modulus * 0.008 * 0.015 / (50e6 * (0.015 - a) ** 2)
    assert group["width_over_nucleation"] == pytest.approx(16e3 / nucleation, rel=1e-12)
    assert group["burial"] == 0.0 and group["strengthening_depth"] == pytest.approx(24 / 16)


def test_the_blocks_stiffness_is_a_surface_breaking_cracks():
    """K = 2 G / (pi W): mean slip of a mode-III crack of half-width W under stress drop dtau is (pi / 2) dtau W / G
    (Knopoff 1958), so K = dtau / slip."""
    assert ladder.block_stiffness(15e3, 30e9) == pytest.approx(2 * 30e9 / (math.pi * 15e3), rel=1e-15)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.3, 1.9), st.floats(2.8, 5.0), st.floats(0.0, 0.15), st.floats(0.0, 1.0), st.floats(0.3, 2.5),
       st.floats(1e7, 1e11))
def test_a_range_brackets_its_centre_evenly_in_log(log_ratio, log_process, ramp, deep, strengthening, raw):
    """Every 95 % range holds its corrected value, symmetric in ln, and no narrower than t s (leverage >= 0)."""
    table = ladder.load_calibration()
    group = {"width_over_nucleation": math.exp(log_ratio), "width_over_process_zone": math.exp(log_process),
             "burial": 0.0, "ramp": ramp, "strengthening_depth": deep, "strengthening_ratio": strengthening}
    for quantity in ladder.QUANTITIES:
        band = ladder.predict(quantity, raw, group, table)
        assert band["low"] < band["value"] < band["high"]
        assert math.log(band["high"] / band["value"]) == pytest.approx(math.log(band["value"] / band["low"]), rel=1e-9)
        floor = table[quantity]["t_quantile"] * table[quantity]["residual_sd"]
        assert math.log1p(band["half_width"]) >= floor * (1 - 1e-12)


def test_the_held_out_faults_fall_inside_their_ranges():
    """Recomputed from the shipped calibration: each held-out 2-D answer (benchmarks/ladder_designs.py, a draw
    that never entered the fit) against the range the one slider declares for it."""
    table = ladder.load_calibration()
    rows = json.loads(HELD_OUT.read_text())["rows"]
    checked = held = 0
    for row in rows:
        if ladder.outside_box(row["group"], table):
            continue
        for quantity in ladder.QUANTITIES:
            if quantity not in row:
                continue
            band = ladder.predict(quantity, row[quantity]["block"], row["group"], table)
            checked += 1
            held += band["low"] <= row[quantity]["two_d"] <= band["high"]
    assert checked >= 20
    assert held / checked >= 0.95, f"{held} of {checked} held-out answers inside their 95 % ranges"


@pytest.mark.parametrize("position, seed, name", [
    (position, seed, path.name)
    for position, (seed, (_, path)) in enumerate(load_benchmark("ladder_designs").FRESH_DRAWS.items())])
def test_a_fresh_draw_falls_inside_the_ranges_a_user_is_given(position, seed, name):
    """benchmarks/results/ladder_fresh.json, ladder_fresh_second.json, ... ladder_fresh_eighth.json: a third to a
    tenth draw over the box (seeds 68002, 68012, 68014, 68031, 68041, 68061, 68071, 68081), each run after the ranges
    were shipped. Each fault's
    own scene goes through faultslip.run(..., method="one_slider"), as a user's would, and its recurrence and
    zone-mean slip ranges, in s and m, are read against the fault's 2-D answer (the calibration's reading of it: an
    unsettled run through its mean interval). The misses are no more than a 95 % range allows (binomial, 1 %
    level), and the summary docs/ladder.md quotes is these counts."""
    from scipy import stats

    from faultslip.models.fault_2d.calibration import Design

    two_d_answer = load_benchmark("ladder_calibration").two_d_answer
    rows = json.loads((RESULTS / name).read_text())["rows"]
    counts = {"recurrence": [0, 0], "mean_slip": [0, 0]}
    for row in rows:
        answer = two_d_answer(row)
        if answer is None:
            continue
        result = faultslip.run(Design(**row["design"]).two_d(3.0), method="one_slider")
        if result.values["recurrence_range"] is None:
            assert any("outside the calibrated box" in note for note in result.notes)
            continue
        for quantity, key, unit in (("recurrence", "recurrence_range", "s"),
                                    ("mean_slip", "mean_slip_per_event_range", "m")):
            low, high = (bound.to(unit).magnitude for bound in result[key])
            counts[quantity][0] += 1
            counts[quantity][1] += bool(low <= answer[quantity] <= high)
    draw = json.loads(HELD_OUT.read_text())["fresh"][position]
    assert (draw["seed"], draw["file"]) == (seed, name)
    summary = draw["summary"]
    for quantity, (checked, held) in counts.items():
        assert checked >= 30, (quantity, checked)
        assert checked - held <= stats.binom.ppf(0.99, checked, 0.05), f"{quantity}: {held} of {checked} inside"
        assert (summary[quantity]["held_out"], summary[quantity]["holds"]) == (checked, held)


def test_every_rung_reads_the_same_scene():
    """The one slider of BP1's scene holds the 2-D answer of that scene in recurrence and in surface slip per event
    (the 2-D run on 3 elements per L_b in benchmarks/results/fault_2d_designs.json; 78.3 yr, 2.47 m at the
    surface). Its slip averaged over the rupture zone (2.294 m) lies just below its 95 % range's bottom (2.299 m):
    BP1 is among the calibration's largest residuals, and a 95 % range misses one fault in twenty."""
    rows = json.loads((ROOT / "benchmarks" / "results" / "fault_2d_designs.json").read_text())["rows"]
    bp1 = next(row for row in rows if row["design"]["name"] == "SEAS BP1")
    for scene in ("seas_bp1.toml", "rsf_fault_bp1.toml"):
        result = faultslip.run(CONFIGS / scene, method="one_slider")
        assert result.method == "one_slider"
        low, high = (bound.to("s").magnitude for bound in result["recurrence_range"])
        assert low <= bp1["recurrence_2d"] <= high
        low, high = (bound.to("m").magnitude for bound in result["slip_per_event_range"])
        assert low <= bp1["surface_slip_2d"] <= high
        low, high = (bound.to("m").magnitude for bound in result["mean_slip_per_event_range"])
        assert 0.99 * low <= bp1["mean_slip_2d"] <= high


@pytest.mark.parametrize("scene, rung", [("lab_glass_dry.toml", "fault_2d"), ("nanoscale_seed001.toml", "one_slider"),
                                         ("asperity_seed004.toml", "fault_3d")])
def test_a_rung_asked_of_a_scene_off_the_ladder_says_what_runs_the_rungs(cli, scene, rung):
    """A laboratory scene is not a fault: --model with a rung, its estimate, and model-error on it are refused in one
    sentence that names the rungs, a fault scene that runs them and where the scene's own methods are listed (the
    spring slider had said only that 'fault_2d' is not one of its methods; model-error, that [lab] is no
    rate-and-state table). A rate-and-state fault is on the ladder: its own refusal names the rungs it reaches."""
    for words in (("run", CONFIGS / scene, "--model", rung), ("run", CONFIGS / scene, "--model", rung, "--estimate")):
        result = cli(*words)
        assert_clean_error(result)
        assert f"'{rung}' is a rung of a fault's ladder" in result.err and "seas_bp1.toml" in result.err
        assert "faultslip methods" in result.err
    result = cli("model-error", CONFIGS / scene)
    assert_clean_error(result)
    assert "give a fault scene" in result.err and "seas_bp1.toml" in result.err
    with pytest.raises(InputError, match="is a rung of a fault's ladder"):
        faultslip.run(CONFIGS / scene, model=rung)
    result = cli("run", CONFIGS / "rsf_block_bp1.toml", "--model", "fault_3d")
    assert_clean_error(result)
    assert "one_slider, fault_2d, got 'fault_3d'" in result.err


def test_outside_the_box_the_one_slider_declares_nothing():
    result = faultslip.run(CONFIGS / "fault_2d_small.toml", method="one_slider")
    assert result.estimated_relative_error is None
    assert result.values["recurrence_range"] is None
    assert any("outside the calibrated box" in note for note in result.notes)


def test_outside_the_box_a_budget_expects_the_correction_at_the_boxs_nearest_point():
    """Below the box (W / h* 0.55-1.2), the recurrence a budget counts events by is the correction with each group
    clamped to its calibrated range: recomputed for each saved fault as recorded (a changed model without a rerun
    fails), within 2x of every settled fault's 2-D recurrence, and at its worst nearer it than the block's worst or
    the block times the calibration's median ratio. Inside the box it is the corrected answer itself."""
    bench = load_benchmark("ladder_outside_box")
    result = json.loads((ROOT / "benchmarks" / "results" / "ladder_outside_box.json").read_text(encoding="utf-8"))
    table = ladder.load_calibration()
    distance = {"clamped": [], "median_ratio": [], "block": []}
    for row in result["rows"]:
        design = bench.Design(**row["design"])
        predicted = bench.predictions(design)
        assert predicted["outside"], row["design"]["name"]
        for key in ("block", "median_ratio", "clamped"):
            assert predicted[key] == pytest.approx(row["predicted"][key], rel=1e-9), (row["design"]["name"], key)
        fault = design.two_d(bench.ELEMENTS_PER_PROCESS_ZONE).fault.description()
        assert ladder.expected_recurrence(fault, table) == pytest.approx(predicted["clamped"], rel=1e-12)
        if row["sequence"] != "unsettled":
            assert 0.5 <= predicted["clamped"] / row["recurrence_2d"] <= 2.0, row["design"]["name"]
            for key in distance:
                distance[key].append(abs(math.log(predicted[key] / row["recurrence_2d"])))
    assert len(distance["clamped"]) >= 10
    assert max(distance["clamped"]) < min(max(distance["block"]), max(distance["median_ratio"]))
    inside = read_fault_2d_scene(ROOT / "configs" / "rsf_fault_bp1.toml").fault.description()
    raw, group = ladder.block_answer(inside, cycles=2)
    assert not ladder.outside_box(group, table)
    assert ladder.clamped_recurrence(raw["recurrence"], group, table) == pytest.approx(
        ladder.predict("recurrence", raw["recurrence"], group, table)["value"], rel=1e-12)


def test_a_tolerance_the_one_slider_cannot_meet_runs_the_2d_fault_of_the_same_scene():
    """The small scene (4.1 elements per L_b, outside the one slider's box) at a tolerance its one run can declare
    (the kind-change term counted: about 0.53)."""
    result = faultslip.run(CONFIGS / "fault_2d_small.toml", tolerance=0.6)
    assert result.method == "fault_2d"
    assert result.values["escalated_from"] == "one_slider"
    assert "outside the one slider's calibration" in result.method_reason
    assert result.values["elements"] == 80  # the scene's own fault, not a rebuilt one
    assert result.estimated_relative_error <= 0.6
    assert result["cpu_time"].magnitude > 0 and result["estimated_seconds"].magnitude > 0
    # the scene's fault_length (Mw only) is named with what the rung above, the 3-D fault, would declare: its
    # burial-0 patch is shallower than every patch the 3-D comparison measured, so nothing is
    assert any("infinitely long along strike" in note and "not declared" in note for note in result.notes)
    assert any("the 2-D fault is the top rung" in note for note in result.notes)


def test_a_tolerance_below_what_the_2d_fault_can_declare_is_refused_before_any_work(cli, monkeypatch, tmp_path):
    """BP1's scene on 40 m elements resolves L_b = 342 m 8.5 times, and one run declares 8.5 % in recurrence for
    its element size (the kind-change term one run cannot see, analysis.single_run_error): a tolerance below it
    ran the 2-D fault for its CPU and then warned. It is refused before any run, naming the fix; at 10 % it runs
    (stood in for here). On the 100 m elements it had, 10 % is refused too, naming the element size that meets it,
    and that size does."""
    from faultslip.models.fault_2d import analysis, family
    from conftest import assert_clean_error

    ran = []
    monkeypatch.setattr(family, "simulate_fault", lambda *args, **kwargs: ran.append(args) or 1 / 0)
    scene = read_fault_2d_scene(CONFIGS / "rsf_fault_bp1.toml")
    floor = analysis.single_run_error(scene.fault.process_zone() / scene.fault.element_size)
    assert family.floor_error(scene) == pytest.approx(floor + 10 * scene.rtol, rel=1e-12)  # the two add
    assert analysis.kind_change_error(scene.resolution) == floor and 0.08 < floor < 0.09
    for args in (("--tolerance", "0.05"), ("--model", "fault_2d", "--tolerance", "0.01")):
        refused = cli("run", CONFIGS / "rsf_fault_bp1.toml", *args)
        assert_clean_error(refused, "cannot meet" if "--model" in args else "no rung meets", "element_size")
    assert not ran
    with pytest.raises(ZeroDivisionError):  # 10 % is reachable: the 2-D run starts
        family.run(scene, tolerance=0.1)
    assert len(ran) == 1
    coarse = tmp_path / "coarse.toml"
    coarse.write_text((CONFIGS / "rsf_fault_bp1.toml").read_text().replace('element_size = "40 m"',
                                                                           'element_size = "100 m"'))
    refused = cli("run", coarse, "--tolerance", "0.1")
    assert_clean_error(refused, "no rung meets", "--richardson")
    named = refused.err.split('element_size = "')[1].split('"')[0]
    size = to_si_scalar(named, "length", "size")
    assert family.floor_error(read_fault_2d_scene(coarse).with_values(element_size=size)) <= 0.1
    # and not much finer than the fewest elements per L_b that meet it (the size named divides the fault)
    fewest = analysis.kind_checked_resolution(0.1 - 10 * scene.rtol)
    assert analysis.single_run_error(0.99 * fewest) + 10 * scene.rtol > 0.1
    assert fewest <= scene.fault.process_zone() / size <= 1.2 * fewest
    assert len(ran) == 1
    # a tolerance no element size a run can hold declares is refused as such
    assert_clean_error(cli("run", coarse, "--tolerance", "1e-300"), "no element size a run can hold")


def test_the_cli_gives_ranges_in_seconds_and_metres():
    done = subprocess.run([sys.executable, "-m", "faultslip.cli", "run", str(CONFIGS / "seas_bp1.toml"), "--model",
                           "one_slider", "--json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["recurrence_range"]["units"] == "s" and len(report["recurrence_range"]["value"]) == 2
    assert report["slip_per_event_range"]["units"] == "m"
    bad = subprocess.run([sys.executable, "-m", "faultslip.cli", "run", str(CONFIGS / "seas_bp1.toml"), "--model",
                          "three_d"], capture_output=True, text=True)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1


def _two_d_runs():
    """Every 2-D run behind the calibration and the held-out test: (name, run, the fault's block and groups)."""
    from faultslip.models.fault_2d.calibration import Design

    rows = (json.loads((ROOT / "benchmarks" / "results" / "fault_2d_designs.json").read_text())["rows"]
            + json.loads((ROOT / "benchmarks" / "results" / "ladder_designs.json").read_text())["rows"])
    for row in rows:
        if row["sequence"] == "unsettled" and len(row["intervals"]) < 4:
            continue
        block, group = ladder.block_answer(Design(**row["design"]).two_d(3.0).fault.description())
        yield row["design"]["name"], row, block, group


def _partial_share(row):
    return (row["events"] - row["system_events"]) / row["system_events"]


def test_the_two_kinds_of_2d_sequence_lie_apart():
    """The kind a 2-D run is counted as (partial events per system-size event, at least 0.25 where they
    interleave: benchmarks/ladder_regimes.py) is not an artefact of that threshold: no run lies near it."""
    shares = [_partial_share(row) for _, row, _, _ in _two_d_runs()]
    assert len(shares) >= 120
    assert not [share for share in shares if 0.15 <= share <= 0.35]
    assert 0.3 <= np.mean([share >= 0.25 for share in shares]) <= 0.7  # both kinds are common over the box


def test_interleaved_partial_events_lengthen_the_recurrence_the_groups_predict():
    """At equal groups, a 2-D fault that interleaves partial events has the longer system-size recurrence: the
    shipped correction's residual, recomputed from the 2-D runs, is positive on one kind and negative on the other,
    as the calibration file (which the one slider's report quotes) states. Told the kind, a fit within each kind
    on the calibration faults still declares held-out ranges wider than +-25 % on average (docs/ladder.md)."""
    table = ladder.load_calibration()
    beta = np.asarray(table["recurrence"]["coefficients"])
    train = {True: [], False: []}
    test = []
    for name, row, block, group in _two_d_runs():
        residual = math.log(row["recurrence_2d"] / block["recurrence"]) - float(ladder.features(group) @ beta)
        kind = _partial_share(row) >= 0.25
        if name.startswith("held out"):
            test.append((kind, group, block, row))
        elif row["sequence"] != "unsettled":
            train[kind].append((group, math.log(row["recurrence_2d"] / block["recurrence"]), residual))
    limits = table["limits"]["recurrence"]
    for kind, key in ((True, "mean_residual_interleaving"), (False, "mean_residual_single")):
        assert np.mean([r for _, _, r in train[kind]]) == pytest.approx(limits[key], abs=0.03)
    assert limits["mean_residual_interleaving"] > 0 > limits["mean_residual_single"]
    fits = {kind: ladder.fit([g for g, _, _ in rows], np.array([y for _, y, _ in rows])) for kind, rows in train.items()}
    widths = [ladder.predict("recurrence", block["recurrence"], group, {"recurrence": fits[kind]})["half_width"]
              for kind, group, block, _ in test if not ladder.outside_box(group, table)]
    assert len(widths) >= 30 and np.mean(widths) > 0.25


def test_the_one_sliders_report_says_why_its_range_is_wide():
    result = faultslip.run(CONFIGS / "seas_bp1.toml", method="one_slider")
    limits = ladder.load_calibration()["limits"]
    note = next(note for note in result.notes if "two kinds" in note)
    assert f"on {limits['calibration_interleaving']} of {limits['calibration_faults']} calibration faults" in note
    assert "--model fault_2d" in note


def test_a_rung_without_a_range_neither_holds_nor_misses_the_answer_above():
    """model-error's comparison (the 2-D and 3-D ladders share it): a range holds where it brackets the top
    rung's recurrence and slip, misses where it brackets either not, and is null where no range is declared."""
    from faultslip.fault.ladder import ladder_report

    def rung(name, recurrence, slip, band=None, slip_band=None):
        return {"name": name, "recurrence": recurrence, "slip": slip, "recurrence_range": band, "slip_range": slip_band,
                "error": None if band is None else 0.2, "cpu_time": 1.0}

    top = rung("fault_3d", 100.0, 2.0, (99.0, 101.0), (1.9, 2.1))
    rungs = [rung("none", 90.0, 1.8), rung("holds", 95.0, 1.9, (80.0, 110.0), (1.5, 2.5)),
             rung("slip_misses", 95.0, 1.0, (80.0, 110.0), (0.8, 1.2)), rung("misses", 50.0, 1.0, (40.0, 60.0)), top]
    values = ladder_report("t", rungs, 0.25, "3-D", "slip per event")
    assert values["none_range_holds"] is None
    assert values["holds_range_holds"] is True
    assert values["slip_misses_range_holds"] is False and values["misses_range_holds"] is False
    assert values["none_meets_tolerance"] is False and values["holds_meets_tolerance"] is True


def test_system_size_events_are_the_ones_that_break_the_zone_not_the_surface():
    """On a buried fault the surface, in the strengthening cap, can slip most in the small events: the events that
    break the velocity-weakening zone are the system-size ones."""
    from faultslip.models.fault_2d.analysis import system_size

    weakening = np.array([False, False, True, True, True, True])
    slip = np.array([[0.02, 0.05, 2.0, 2.2, 2.1, 1.8],     # breaks the zone, the cap barely moves
                     [0.30, 0.40, 0.1, 0.0, 0.0, 0.0],     # a small shallow event: the surface's largest slip
                     [0.02, 0.04, 1.9, 2.0, 2.1, 1.9],
                     [0.00, 0.00, 0.0, 0.0, 0.4, 0.9]])    # a partial event at the base
    assert system_size(slip, weakening).tolist() == [0, 2]
    assert system_size(slip[:0], weakening).size == 0
    assert system_size(slip, np.zeros(6, bool)).tolist() == [0, 2]  # nothing weakens: the whole fault's mean


def test_the_2d_rung_and_the_one_slider_agree_on_a_buried_fault():
    """A buried held-out fault (benchmarks/results/ladder_designs.json, 'held out 29': a cap of 0.22 W, partial
    events interleaved): the 2-D rung reports the recurrence and mean slip of the events that break the zone, as the
    calibration counted them (its surface slips most in partial events, which the rung once took for the system-size
    ones: twice the recurrence and 1e-4 m of slip), and the one slider's ranges for the same fault hold them."""
    from faultslip.fault.ladder import one_slider_report
    from faultslip.models.fault_2d.calibration import PLATE_RATE, Design, geometric_stiffness
    from faultslip.models.fault_2d.family import simulate_fault
    from faultslip.dynamics.rate_state.slider import fault_cycles

    rows = json.loads((ROOT / "benchmarks" / "results" / "ladder_designs.json").read_text())["rows"]
    row = next(row for row in rows if row["design"]["name"] == "held out 29")
    design = Design(**row["design"])
    block = fault_cycles(design.slider(geometric_stiffness(design.seismogenic_width)), PLATE_RATE, cycles=3)
    scene = design.two_d(3.0, duration=10 * block.recurrence)
    result = simulate_fault(scene, settle_tolerance=0.01)
    recurrence = result["recurrence_interval"].to("s").magnitude
    mean_slip = result["mean_slip_per_event"].to("m").magnitude
    assert recurrence == pytest.approx(row["recurrence_2d"], rel=1e-3)
    assert mean_slip == pytest.approx(row["mean_slip_2d"], rel=1e-3)
    report = one_slider_report(scene.fault.description(), "test")
    low, high = report["recurrence_range"]
    assert low <= recurrence <= high
    low, high = report["mean_slip_per_event_range"]
    assert low <= mean_slip <= high


def test_the_gaussian_process_of_the_limits_table_recovers_a_known_function_and_its_noise():
    """The nonlinear fit that docs/ladder.md sets beside the linear one: on a smooth function of two of three
    columns with normal noise of sd 0.1, its mean follows the function to well inside the noise, its sd is the
    noise's (the function being learnt), and its 95 % band holds about 95 % of fresh points."""
    gaussian_process = load_benchmark("ladder_calibration").gaussian_process
    rng = np.random.default_rng(1)

    def truth(x):
        return np.sin(2.0 * x[:, 0]) + 0.5 * x[:, 1] ** 2

    x_train, x_test = rng.uniform(-1.5, 1.5, (120, 3)), rng.uniform(-1.2, 1.2, (400, 3))
    y_train = truth(x_train) + rng.normal(0.0, 0.1, 120)
    y_test = truth(x_test) + rng.normal(0.0, 0.1, 400)
    mean, sd = gaussian_process(x_train, y_train, x_test)
    assert np.sqrt(np.mean((mean - truth(x_test)) ** 2)) < 0.05
    assert np.median(sd) == pytest.approx(0.1, rel=0.25)
    assert 0.9 <= np.mean(np.abs(y_test - mean) <= 1.96 * sd) <= 0.99


def test_nearest_neighbours_name_a_separable_kind_and_choose_k_by_leave_one_out():
    nearest_kind = load_benchmark("ladder_calibration").nearest_kind
    rng = np.random.default_rng(2)
    x_train, x_test = rng.normal(size=(80, 4)), rng.normal(size=(200, 4))
    labels = (x_train[:, 0] * x_train[:, 1] > 0).astype(float)  # no line separates it
    guessed, k = nearest_kind(x_train, labels, x_test)
    assert k % 2 == 1 and 1 <= k <= 15
    assert np.mean(guessed == (x_test[:, 0] * x_test[:, 1] > 0)) > 0.75


def test_the_shipped_correction_is_the_fit_of_the_runs_and_more_designs_cannot_bring_it_to_25_percent():
    """Provenance of data/ladder_calibration.json: refitted here from the 2-D runs (the benchmark's own choice of
    calibration faults), the correction and its residual sd are the shipped ones. The declared range is
    t s sqrt(1 + leverage) about it; with unlimited designs t tends to the normal quantile and the leverage to 0,
    leaving the residual sd s: wider than +-25 % for the recurrence and the slip (docs/ladder.md, what limits
    the range)."""
    bench = load_benchmark("ladder_calibration")
    table = ladder.load_calibration()
    old = json.loads(bench.OLD.read_text())["rows"]
    new = json.loads(bench.NEW.read_text())["rows"]
    rows = old + [row for row in new if row["design"]["name"].startswith("calibration")]
    train = [item for item in map(bench.prepared, rows) if item is not None]
    for quantity in ("recurrence", "mean_slip"):
        pairs = bench.targets(train, quantity)
        refit = ladder.fit([item["group"] for item, _ in pairs], np.array([y for _, y in pairs]))
        assert refit["faults"] == table[quantity]["faults"]
        assert refit["residual_sd"] == pytest.approx(table[quantity]["residual_sd"], rel=1e-6)
        assert np.allclose(refit["coefficients"], table[quantity]["coefficients"], rtol=1e-5, atol=1e-8)
        floor = math.expm1(1.959963984540054 * refit["residual_sd"])
        assert floor > 0.25, (quantity, floor)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(min_value=-3.0, max_value=3.0, allow_nan=False), min_size=1, max_size=80),
       st.sampled_from([0.5, 0.9, 0.95]))
def test_the_narrowest_width_is_the_least_that_holds_the_level(residuals, level):
    """The narrowest range's width (docs/ladder.md, what limits the range): at least ``level`` of the residuals lie
    within it, and any narrower width holds fewer than ``level``."""
    width = load_benchmark("ladder_calibration")._narrowest_log_width(residuals, level)
    size = np.abs(np.array(residuals))
    assert np.mean(size <= width) >= level
    assert np.mean(size < width) < level


def test_no_range_of_one_width_about_the_shipped_centre_holds_the_unseen_faults_within_25_percent():
    """Recomputed from the rows the benchmark saved (each unseen fault's 2-D answer and the shipped centre), the
    narrowest single width holding 95 % of the held-out and fresh faults inside the box is the one the limits
    record, and wider than +-25 %: the half-width the issue asks for is out of reach of any range about this
    centre, even one set with the answers in hand."""
    held = json.loads(HELD_OUT.read_text())
    rows = [row for row in held["rows"] + [r for draw in held["fresh"] for r in draw["rows"]] if not row["outside"]]
    narrowest = held["limits"]["narrowest"]
    for quantity in ("recurrence", "mean_slip"):
        size = np.sort([abs(math.log(row[quantity]["two_d"] / row[quantity]["value"])) for row in rows])
        width = math.expm1(size[math.ceil(0.95 * size.size) - 1])
        assert size.size == narrowest[quantity]["unseen_faults"] >= 60
        assert width == pytest.approx(narrowest[quantity]["unseen"], rel=1e-9)
        assert width > 0.25
        # refitted on every fault, and with a width of its own per band of W/h*: still wider
        assert min(narrowest[quantity][fit] for fit in ("refitted", "by_band")) > 0.25


@settings(max_examples=20, deadline=None)
@given(st.floats(min_value=0.01, max_value=100.0))
def test_a_design_starts_in_steady_state_at_the_speed_it_is_told(factor):
    """Design.two_d(initial_speed=V): every element's initial stress and state give V back through the
    regularised law, V = 2 V_0 exp(-psi / a) sinh[(tau - eta V) / (a sigma_n)] (BP1 eqs. 3, 8-9)."""
    from faultslip.models.fault_2d.calibration import PLATE_RATE, Design

    speed = factor * PLATE_RATE
    fault = Design("start", 2.0, 0.009).two_d(3.0, initial_speed=speed).fault
    x = (fault.initial_shear_stress - fault.damping * speed) / (fault.a * fault.normal_stress)
    log_speed = np.log(2 * fault.reference_speed) - fault.initial_state / fault.a + x + np.log1p(-np.exp(-2 * x)) - math.log(2)
    assert np.allclose(log_speed, math.log(speed), rtol=0, atol=1e-9)


def test_the_starts_file_says_what_its_runs_show():
    """benchmarks/results/ladder_regimes.json's starts: the usual start is each held-out fault's recorded run, and
    the summary (docs/ladder.md quotes it) is recomputed from the runs it lists."""
    regimes = json.loads((ROOT / "benchmarks" / "results" / "ladder_regimes.json").read_text())
    if "starts" not in regimes:
        pytest.skip("ladder_regimes.py --part start has not been run")
    block = regimes["starts"]
    recorded = {row["design"]["name"]: row for row in
                json.loads((ROOT / "benchmarks" / "results" / "ladder_designs.json").read_text())["rows"]}
    for fault in block["faults"]:
        usual = fault["starts"]["1"]
        assert usual["recurrence"] == recorded[fault["name"]]["recurrence_2d"]
        for factor, change in fault["recurrence_change"].items():
            assert change == pytest.approx(fault["starts"][factor]["recurrence"] / usual["recurrence"] - 1)
    summary = block["summary"]
    settled = [f for f in block["faults"] if f["starts"]["1"]["sequence"] == "periodic"]
    moved = {f["name"] for f in settled if f["largest_change"] > summary["same_answer_within"]}
    assert summary["same_answer"] == len(settled) - len(moved)
    assert {entry["name"] for entry in summary["elsewhere"]} == moved
    assert summary["faults"] == len(block["faults"]) >= 30


def test_a_ladders_estimate_is_its_rungs_one_after_another_and_no_rung_runs(cli, monkeypatch):
    """`model-error SCENE --estimate`: the one slider's cycles, the antiplane rung where the scene dips, the 2-D
    fault and, with --include-3d, the 3-D fault, each from its own cost model, summed; nothing runs. A scene with
    no ladder, or none given, is one sentence."""
    from faultslip.models.fault_2d import family as fault_2d_family

    ran = []
    monkeypatch.setattr(fault_2d_family, "simulate_fault", lambda *args, **kwargs: ran.append(args))
    surface = CONFIGS / "fault_2d_surface_small.toml"
    ladder = cli("model-error", surface, "--include-3d", "--estimate", "--json")
    assert ladder.code == 0, ladder.err
    loaded = read_fault_2d_scene(surface)
    rungs = [faultslip.models.estimate(surface, "run", method="one_slider"), loaded.estimate(in_this_process=True),
             faultslip.models.estimate(surface, "run", method="fault_3d")]
    # each from its cost model; the imports an estimate measures (its process's own) are apart
    assert modelled_seconds(ladder.json) == pytest.approx(sum(rung.modelled_seconds for rung in rungs), rel=1e-9)
    assert "the 3-D rung (" in ladder.out and "the 2-D rung (" in ladder.out
    dipping = cli("model-error", CONFIGS / "fault_2d_dipping_small.toml", "--estimate")
    assert dipping.code == 0 and "the antiplane rung (" in dipping.out and "the 3-D rung" not in dipping.out
    three = cli("model-error", CONFIGS / "fault_3d_small.toml", "--estimate")
    folded = " ".join(three.out.split())  # the report folds a long description over lines
    assert three.code == 0 and "the 2-D rung (the middle column)" in folded and "the 3-D rung (" in folded
    assert not ran
    assert_clean_error(cli("model-error", CONFIGS / "rsf_block_bp1.toml", "--estimate"), "no ladder")
    assert_clean_error(cli("model-error", "--estimate"), "give the scene")


def test_a_ladder_over_its_budget_is_refused_before_any_rung_runs(cli, monkeypatch):
    """The whole ladder is budgeted before its first rung: a 3-D scene's, whose 3-D rung alone is over the budget,
    is refused in one sentence naming that rung, with no 2-D run made (it had run the lower rungs first)."""
    from faultslip.models.fault_2d import family as fault_2d_family

    ran = []
    monkeypatch.setattr(fault_2d_family, "simulate_fault", lambda *args, **kwargs: ran.append(args))
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "2")  # the 3-D rung's estimate is seconds, the others' less
    assert_clean_error(cli("model-error", CONFIGS / "fault_3d_small.toml"), "the 3-D rung (", "--allow-large")
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "0.05")  # below the 2-D rung's steps alone (0.3 s), loaded or not
    assert_clean_error(cli("model-error", CONFIGS / "fault_2d_small.toml"), "the 2-D rung (", "--allow-large")
    assert not ran


def test_runs_one_after_another_keep_where_any_lies_outside_its_fit():
    """A sum of estimates keeps each one's outside-the-fit sentences, so the budget refuses the whole as it would
    the part (they had been dropped)."""
    from faultslip.io import budget

    inside = budget.Estimate("a run", seconds=1.0)
    outside = budget.Estimate("another", seconds=2.0, outside_fit=("its W/h* is 40, fitted 0.5 to 8",))
    both = budget.one_after_another("both", [inside, outside, outside])
    assert both.seconds == 5.0 and both.outside_fit == ("its W/h* is 40, fitted 0.5 to 8",)
    with pytest.raises(InputError, match="fitted on other scenes"):
        budget.check(both)


@settings(max_examples=200, deadline=None)
@given(truth=st.floats(1e-3, 1e12), numerical=st.floats(0.0, 0.05), model=st.floats(0.0, 0.9),
       numerical_share=st.floats(-1.0, 1.0), model_share=st.floats(-1.0, 1.0))
def test_a_lower_rungs_widened_range_holds_every_answer_its_errors_allow(truth, numerical, model, numerical_share,
                                                                        model_share):
    """A rung's answer off the exact one by its numerical error, whose exact answer is off the rung above by its
    model error (each measured as |value / truth - 1|), lies where with_model_error's range says: the errors
    compound, and the range inverts the definition ([v / (1 + e), v / (1 - e)]). The symmetric v (1 -/+ e) it had
    missed the answer above where the lower rung falls short by more than e / (1 + e)."""
    exact = truth * (1 + model_share * model)
    value = exact * (1 + numerical_share * numerical)
    rung = ladder.with_model_error({"recurrence": value, "slip": 2 * value, "error": numerical}, model)
    error = rung["error"]
    assert error == pytest.approx((1 + numerical) * (1 + model) - 1)
    if error >= 1:
        assert rung["recurrence_range"] is None and rung["slip_range"] is None
        return
    for key, scale in (("recurrence_range", 1.0), ("slip_range", 2.0)):
        low, high = rung[key]
        assert low <= scale * truth * (1 + 1e-12) and scale * truth <= high * (1 + 1e-12)


def test_the_one_sliders_range_on_a_dipping_fault_inverts_the_dip_error(monkeypatch):
    """On a plane-strain scene outside the one slider's calibration against plane strain (BP3's fault at 20
    degrees, below the dips measured), its calibrated range against antiplane widens by the antiplane rung's
    declared dip error e to [low / (1 + e), high / (1 - e)]; from e = 1 on there is no upper bound, so no range, and
    the note says why."""
    scene = read_fault_2d_scene(CONFIGS / "seas_bp3_thrust60.toml").with_values(dip=20.0)
    flat = faultslip.run(scene.antiplane(), method="one_slider")
    for declared in (0.3, 0.75):
        monkeypatch.setattr(ladder.dip_error, "declared", lambda dip, width_over_nucleation, e=declared: e)
        values = faultslip.run(scene, method="one_slider").values
        low, high = (float(v.to("s").magnitude) for v in values["recurrence_range"])
        flat_low, flat_high = (float(v.to("s").magnitude) for v in flat.values["recurrence_range"])
        assert low == pytest.approx(flat_low / (1 + declared)) and high == pytest.approx(flat_high / (1 - declared))
    monkeypatch.setattr(ladder.dip_error, "declared", lambda dip, width_over_nucleation: 1.2)
    result = faultslip.run(scene, method="one_slider")
    assert result.values["recurrence_range"] is None
    assert any("no upper bound" in note for note in result.notes)


@settings(max_examples=15, deadline=None)
@given(critical_slip=st.floats(0.002, 0.032), normal_stress=st.floats(25e6, 100e6),
       seismogenic_depth=st.floats(7.5e3, 22.5e3))
def test_the_one_sliders_declared_error_is_known_before_its_block_runs(critical_slip, normal_stress,
                                                                      seismogenic_depth):
    """ladder.declared_error reads a fault's groups alone, so an estimate can tell whether a tolerance stops at
    the one slider: it is exactly what one_slider_report declares once the block has run, on BP1 moved over the
    calibration box (D_c x0.25-4, sigma_n x0.5-2, H x0.5-1.5) and beyond it (None there, as the report's)."""
    scene = read_fault_2d_scene(CONFIGS / "rsf_fault_bp1.toml").with_values(
        critical_slip=critical_slip, normal_stress=normal_stress, seismogenic_depth=seismogenic_depth)
    fault = scene.fault.description()
    assert ladder.declared_error(fault) == ladder.one_slider_report(fault, "test")["estimated_relative_error"]


@pytest.mark.parametrize("name", ["rsf_fault_bp1.toml", "fault_2d_small.toml", "fault_2d_dipping_small.toml",
                                  "seas_bp3_thrust60.toml", "fault_2d_surface_small.toml"])
def test_the_declared_error_before_the_block_runs_on_every_kind_of_fault(name):
    """The same on the bundled scenes: inside the box and outside it, surface-breaking and buried, dipping with a
    declared dip error (BP3's thrust) and without one (the small dipping fault)."""
    fault = read_fault_2d_scene(CONFIGS / name).fault.description()
    assert ladder.declared_error(fault) == ladder.one_slider_report(fault, "test")["estimated_relative_error"]


def test_an_estimate_is_of_the_rungs_run_goes_to(monkeypatch):
    """'faultslip run SCENE --tolerance X --estimate' estimated the 2-D run whatever X was, and took a rung run
    refuses. Now: where the one slider's declared error (0.56 on BP1's scene) meets the tolerance, the one slider's
    cost alone, and run stops there; below it, the one slider's and the 2-D fault's, and run escalates; a tolerance
    no rung meets, or a rung that does not exist, is refused in one sentence as run refuses it, before any work."""
    from faultslip.models.fault_2d import family

    path = CONFIGS / "rsf_fault_bp1.toml"
    scene = read_fault_2d_scene(path)
    declared = ladder.declared_error(scene.fault.description())
    assert 0.3 < declared < 0.9
    above = min(0.99, declared * 1.05)
    stops = faultslip.models.estimate(path, tolerance=above)
    assert "one slider" in stops.what and "2-D fault run" not in stops.what
    assert faultslip.run(path, tolerance=above).method == "one_slider"
    escalates = faultslip.models.estimate(path, tolerance=0.1)
    two_d = scene.estimate(in_this_process=True)
    assert escalates.seconds == pytest.approx(two_d.seconds + faultslip.models.estimate(
        path, method="one_slider").seconds, rel=1e-9) and f"{declared:.2g} exceeds the tolerance 0.1" in escalates.what
    # what it leaves out, said: the longer runs a run that ends unsettled makes (each the doubled scene's estimate)
    from dataclasses import replace

    from faultslip.io.progress import duration

    longer = [replace(scene, duration=scene.duration * factor).estimate().seconds for factor in (2, 4)]
    assert longer[0] < longer[1] and escalates.notes == (family.rerun_note(scene, scene.rtol),)
    assert all(f"about {duration(seconds)}" in escalates.notes[0] for seconds in longer)
    assert f"{2 * scene.duration / YEAR:.6g} yr" in escalates.notes[0] and str(family.LONGER_RUNS) in escalates.notes[0]
    assert escalates.notes[0] in escalates.report().notes and not stops.notes
    ran = []
    monkeypatch.setattr(family, "simulate_fault", lambda *args, **kwargs: ran.append(args) or 1 / 0)
    with pytest.raises(ZeroDivisionError):  # and run goes there: the one slider first, then the 2-D run starts
        family.run(scene, tolerance=0.1)
    for options, needle in (({"tolerance": 1e-9}, "no rung meets"), ({"method": "fault_2d", "tolerance": 1e-9},
                                                                     "cannot meet"),
                            ({"method": "bogus"}, "runs on the rungs"),
                            ({"method": "one_slider", "richardson": True}, "ask for --model fault_2d")):
        with pytest.raises(InputError, match=needle):
            faultslip.models.estimate(path, **options)
        with pytest.raises(InputError, match=needle):
            family.run(scene, **options)
    assert len(ran) == 1


def test_a_one_slider_scenes_estimate_is_of_the_2d_fault_it_escalates_to():
    """'faultslip run configs/rsf_block_bp1.toml --tolerance 0.1 --estimate' said 3 ms (the block's 5 cycles) for
    a run that escalates to the 2-D fault it stands for (about 10 s of CPU). Where the block's declared model error
    misses the tolerance, or the 2-D fault is asked for by name, the estimate is now that escalation's own (the
    family's own form and the seed-law form alike); where the block answers, the block's. What run refuses, the
    estimate refuses: an unknown method, a tolerance outside (0, 1), a tolerance on a laboratory scene."""
    from faultslip.models.fault_2d.family import one_slider_refinement
    from faultslip.models.rate_state_slider.family import _own_form
    from faultslip.models.rate_state_slider.scene import model_error_of, read_rate_state_scene
    from faultslip.fault.scene import estimate_scene_rate_state, read_slider_scene

    own = CONFIGS / "rsf_block_bp1.toml"
    older = CONFIGS / "san_andreas_1906_rate_state.toml"
    blocks = {own: read_rate_state_scene(own)}
    seed_law = read_slider_scene(older)
    blocks[older] = _own_form(seed_law.name, estimate_scene_rate_state(seed_law))
    for path, block in blocks.items():
        error = model_error_of(block)[0]
        two_d = one_slider_refinement(block).estimate(in_this_process=True).seconds
        answered = faultslip.models.estimate(path).seconds
        assert 0 < answered < 0.01 * two_d
        assert faultslip.models.estimate(path, tolerance=0.5 * error).seconds == two_d
        assert faultslip.models.estimate(path, method="fault_2d").seconds == two_d
        if error < 1:  # a tolerance is a relative error below 1 (faultslip.ranges.check_tolerance): the seed-law
            # form's block declares 1.5, which only --model one_slider answers
            assert faultslip.models.estimate(path, tolerance=(1 + error) / 2).seconds == answered
        assert faultslip.models.estimate(path, method="one_slider", tolerance=0.5 * error).seconds == answered
        for options, needle in (({"method": "bogus"}, "runs one of"), ({"tolerance": -1.0}, "between 0 and 1")):
            with pytest.raises(InputError, match=needle):
                faultslip.models.estimate(path, **options)
            with pytest.raises(InputError, match=needle):
                faultslip.run(path, **options)
    with pytest.raises(InputError, match="laboratory scene"):
        faultslip.models.estimate(CONFIGS / "rsf_velocity_step.toml", tolerance=0.1)


def test_the_ranges_are_not_widened_by_the_element_size_the_calibration_ran_at():
    """The calibration's 2-D answers are runs at 3 elements per L_b, where one run declares up to 116 %. Read
    against the resolved answers of the unseen faults the resolution benchmark refined (Richardson limits of runs
    to 12 or 24 per L_b: benchmarks/fault_2d_resolution_designs.py, summary ladder.residuals), the faults scatter
    about the shipped centre no less, and 95 % of them still lie beyond ±25 %: the one slider's width is the 2-D
    sequences' own spread, not the calibration's element size (docs/ladder.md, What limits the range)."""
    from faultslip.models.fault_2d.analysis import single_run_error

    sets = load_benchmark("fault_2d_resolution_designs").DRAWS
    for quantity in ("recurrence", "mean_slip"):
        rows = np.array([row[1:] for name in sets for row in json.loads(
            (RESULTS / f"fault_2d_resolution_{name}.json").read_text())["summary"]["ladder"][quantity]["residuals"]])
        assert len(rows) >= 90
        coarse, resolved = np.std(rows, axis=0, ddof=1)
        assert resolved >= 0.95 * coarse > 0.1, (quantity, coarse, resolved)
        assert np.quantile(np.abs(rows[:, 1]), 0.95) > math.log(1.25)
        # the residuals are the coarse and resolved answers about one centre: their difference is the 3 per L_b
        # run's error, within what one run declares there
        assert np.all(np.abs(np.expm1(rows[:, 0] - rows[:, 1])) <= single_run_error(3.0))


def test_a_rung_that_declares_its_slips_own_error_gets_its_slip_range_from_it():
    """The 3-D fault declares slip per event's error apart from the recurrence's (slip_per_event_error): a ladder
    row reads each range from its own error, reports the slip's where it differs, and a model error compounds each;
    a rung declaring one error (the 2-D fault's) reads both ranges from it."""
    from faultslip.contract.result import Result
    from faultslip.io.report import Report

    def result(slip_error):
        report = Report("a rung")
        report.add("recurrence_interval", 100.0, "s").add("slip_per_event", 2.0, "m")
        report.add("estimated_relative_error", 0.05)
        if slip_error is not None:
            report.add("slip_per_event_error", slip_error)
        return Result("fault_3d", report)

    three = ladder.rung_of("fault_3d", result(0.25), 1.0, slip="mean")
    assert three["error"] == 0.05 and three["slip_error"] == 0.25
    assert three["recurrence_range"] == pytest.approx(ladder.truth_range(100.0, 0.05))
    assert three["slip_range"] == pytest.approx(ladder.truth_range(2.0, 0.25))
    assert ladder.truth_range(2.0, 0.25)[0] < 2.0 / 1.05  # wider than the recurrence's error would give
    two = ladder.rung_of("fault_2d", result(None), 1.0)
    assert two["slip_error"] == 0.05 and two["slip_range"] == pytest.approx(ladder.truth_range(2.0, 0.05))
    widened = ladder.with_model_error(three, 0.5)
    assert widened["error"] == pytest.approx(1.05 * 1.5 - 1) and widened["slip_error"] == pytest.approx(1.25 * 1.5 - 1)
    assert widened["slip_range"] == pytest.approx(ladder.truth_range(2.0, 1.25 * 1.5 - 1))
    report = ladder.ladder_report("ladder", [two, three], None, "3-D", "slip per event")
    assert "fault_3d_slip_declared_error" in report and "fault_2d_slip_declared_error" not in report
