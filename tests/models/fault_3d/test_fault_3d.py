"""The 3-D fault: its kernel against Okada's code and the 2-D kernels' exact limits, the FFT along strike against
the dense product, stations, the 2-D fault's stepping and restart on it, SEAS BP5 files and bad scenes."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import load_benchmark

import faultslip
from faultslip.errors import InputError
from faultslip.io.seas import read_seas
from faultslip.models.fault_2d.integrate import YEAR, run_cycles
from faultslip.models.fault_2d.kernel import dense_matrix
from faultslip.models.fault_2d.plane_strain import traction_kernels
from faultslip.models.fault_3d import kernel
from faultslip.models.fault_3d.family import simulate, summarise
from faultslip.models.fault_3d.model import StationGrid
from faultslip.models.fault_3d.scene import load_fault_3d_scene, parse_fault_3d_scene

ROOT = Path(__file__).resolve().parents[3]
SMALL = ROOT / "configs" / "fault_3d_small.toml"
G = 3.2038e10


def _okada_rows():
    return json.loads((ROOT / "tests" / "data" / "okada_dc3d_reference.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize("slip", ["strike", "dip"])
def test_the_kernel_is_okadas_dc3d_to_1e_7_of_the_self_stress(slip):
    """Okada's own Fortran (DC3D, via okada_wrapper; benchmarks/okada_reference.py wrote the numbers) against three
    triangular dislocations a square (cutde): every pair, near and far, surface and buried, agrees to 1e-7 of the
    largest traction (measured 2.4e-8 strike slip, 5.3e-8 dip slip). Okada's DISL1 is left-lateral and DISL2
    reverse on the hanging wall at -y; the kernel's slip is the hanging wall's at +y: the sign is opposite."""
    document = _okada_rows()
    h = document["element_size"]
    rake = "strike" if slip == "strike" else "thrust"
    mine, okada = [], []
    for row in (r for r in document["rows"] if r["slip"] == slip):
        source, (offset, depth_index) = row["source"][1], row["observation"]
        tris = kernel.element_triangles(np.zeros(1), np.array([source * h]), h, 90.0)
        observation = kernel.centres(np.array([offset]), np.array([depth_index]), h, 90.0)
        shear, _, _ = kernel.tractions(observation, tris,
                                       kernel._tdcs_slip(tris, kernel.slip_direction(rake, 90.0)), 90.0, rake,
                                       document["shear_modulus"], document["poisson_ratio"])
        mine.append(shear[0])
        okada.append(row["okada_stress"])
    mine, okada = np.array(mine), np.array(okada)
    assert np.max(np.abs(mine + okada)) <= 1e-7 * np.max(np.abs(okada))


def test_a_long_vertical_fault_is_the_antiplane_kernel():
    """Uniform slip over a row of squares L long is, at its middle, the antiplane strip (the 2-D family's exact
    kernel) to the ends' share, which falls as (W / L)^2: checked at two lengths."""
    errors = []
    for length in (201, 801):
        operator = kernel.StrikeConvolution(length, 6, 1000.0, 90.0, "strike", G, 0.25)
        stress = operator(np.ones(length * 6)).reshape(length, 6)[length // 2]
        exact = dense_matrix(6, 1000.0, G).sum(axis=1)
        errors.append(np.max(np.abs(stress - exact)) / np.max(np.abs(exact)))
    assert errors[1] < 1e-4
    assert 10.0 < errors[0] / errors[1] < 22.0  # (801 / 201)^2 = 15.9


@pytest.mark.parametrize("dip,rake,sense", [(60.0, "thrust", "thrust"), (30.0, "normal", "normal")])
def test_a_long_dipping_fault_is_the_plane_strain_kernels(dip, rake, sense):
    """Dip slip on a long dipping fault is, at its middle, plane strain: the 2-D family's kernels from Muskhelishvili's
    complex potentials (an independent derivation), shear and normal, to the ends' share."""
    length, rows = 801, 5
    operator = kernel.StrikeConvolution(length, rows, 1000.0, dip, rake, G, 0.25)
    both = operator.both(np.ones(length * rows))
    shear = both[: length * rows].reshape(length, rows)[length // 2]
    normal = both[length * rows:].reshape(length, rows)[length // 2]
    shear_2d, normal_2d = traction_kernels(rows, 1000.0, dip, G, 0.25)
    normal_2d = normal_2d if sense == "thrust" else -normal_2d
    scale = np.max(np.abs(shear_2d.sum(axis=1)))
    assert np.max(np.abs(shear - shear_2d.sum(axis=1))) < 1e-4 * scale
    assert np.max(np.abs(normal - normal_2d.sum(axis=1))) < 1e-4 * scale


@pytest.mark.parametrize("dip,rake", [(90.0, "strike"), (90.0, "thrust"), (60.0, "thrust"), (30.0, "normal"),
                                      (45.0, "strike")])
def test_the_fft_along_strike_is_the_dense_product(dip, rake):
    """The operator is exact, not compressed: its product equals every square's own dense column to round-off, and
    every square's own slip unloads it (a negative self term)."""
    strike_count, dip_count = 6, 4
    shear, normal = kernel.dense_matrices(strike_count, dip_count, 1000.0, dip, rake, G, 0.25)
    operator = kernel.StrikeConvolution(strike_count, dip_count, 1000.0, dip, rake, G, 0.25)
    slip = np.random.default_rng(3).normal(size=strike_count * dip_count)
    both = operator.both(slip)
    count = strike_count * dip_count
    assert np.max(np.abs(both[:count] - shear @ slip)) <= 1e-12 * np.max(np.abs(shear @ slip))
    if operator.normal_changes:
        assert np.max(np.abs(both[count:] - normal @ slip)) <= 1e-12 * np.max(np.abs(normal @ slip))
    else:  # strike slip on a vertical fault: the field is odd across the plane, no normal stress changes
        assert np.max(np.abs(normal)) <= 1e-9 * np.max(np.abs(shear))
    assert np.all(np.diag(shear) < 0)


@settings(max_examples=20, deadline=None)
@given(st.lists(st.floats(-2.0, 2.0), min_size=24, max_size=24), st.floats(0.5, 3.0))
def test_the_operator_is_linear_and_translation_invariant(values, scale):
    """K(a s) = a K(s), and a slip shifted along strike shifts the stress with it (away from the ends)."""
    operator = kernel.StrikeConvolution(8, 3, 500.0, 90.0, "strike", G, 0.25)
    slip = np.zeros((8, 3))
    slip[:4] = np.array(values[:12]).reshape(4, 3)
    base = operator(slip.ravel()).reshape(8, 3)
    assert np.allclose(operator(scale * slip.ravel()).reshape(8, 3), scale * base, rtol=1e-12, atol=1e-6)
    shifted = operator(np.roll(slip, 2, axis=0).ravel()).reshape(8, 3)
    assert np.allclose(shifted[2:6], base[0:4], rtol=1e-10, atol=1e-3)


def test_stations_interpolate_a_bilinear_field_exactly():
    scene = load_fault_3d_scene(SMALL)
    fault = scene.fault
    field = 3.0 + 2e-3 * fault.strike_position - 5e-3 * fault.depth
    positions = [(-2000.0, 300.0), (0.0, 1000.0), (1234.0, 555.0)]
    stations = StationGrid(positions, fault)
    expected = [3.0 + 2e-3 * x - 5e-3 * z for x, z in positions]
    assert np.allclose(stations(field), expected, rtol=1e-13)
    with pytest.raises(InputError, match="on the fault"):
        StationGrid([(9e3, 0.0)], fault)


def test_a_stopped_run_resumes_bit_for_bit(tmp_path):
    """The 2-D fault's checkpoints carry a 3-D run: stopped after a checkpoint and resumed, it ends on the same
    bits as a run never stopped."""
    scene = load_fault_3d_scene(SMALL).with_values(element_size=250.0)
    scene.duration = 3 * YEAR
    kwargs = dict(stations=scene.recorder(), operator=scene.operator(), profile_interval=YEAR,
                  coseismic_interval=1.0)
    whole = run_cycles(scene.fault, scene.duration, rtol=1e-6, **kwargs)
    folder = tmp_path / "run"
    with pytest.raises(Exception):
        run_cycles(scene.fault, scene.duration, rtol=1e-6, folder=folder, stop_after_steps=whole.steps // 2,
                   **kwargs)
    resumed = run_cycles(scene.fault, scene.duration, rtol=1e-6, folder=folder, resume=True, **kwargs)
    assert resumed.steps == whole.steps
    assert np.array_equal(resumed.final_slip, whole.final_slip)
    assert np.array_equal(np.asarray(resumed.stations["slip"]), np.asarray(whole.stations["slip"]))


def test_the_small_fault_cycles_balance_the_plate(tmp_path):
    """The small fault's system-size events recur periodically, and over a cycle its patch slips what the plate
    loads it with (V_p T, within 1 %); the SEAS BP5 files read back."""
    result = simulate(SMALL, output_dir=tmp_path / "out")
    run = result.extras["run"]
    interval = result["recurrence_interval"]
    assert result["settled"] and interval > 0
    assert 0.0 < result["estimated_relative_error"] < 0.5
    dataset = result.to_xarray()
    slip = np.asarray(dataset["station_slip"])[:, 1]  # (0, 0.5 km): in the patch
    starts = np.asarray(dataset["event_start"])
    time = np.asarray(dataset["time"])
    first, last = starts[-2], starts[-1]
    cycle = np.interp(last, time, slip) - np.interp(first, time, slip)
    assert cycle == pytest.approx(1e-9 * (last - first), rel=0.01)
    header, names, rows = read_seas(tmp_path / "out" / "fltst_strk+00dp+00.dat")
    assert names[:3] == ["t", "slip_2", "slip_3"] and rows.shape[1] == 8
    for name in ("global.dat", "rupture.dat", "slip_2_depth.dat", "slip_2_strike.dat", "events.csv", "fault_3d.nc"):
        assert (tmp_path / "out" / name).is_file(), name
    assert run.event_count >= 3
    assert summarise(run)["system"].size == run.event_count  # every event ruptures the patch


def test_rupture_times_grow_away_from_the_nucleation_patch():
    """The first event starts in the nucleation patch at the -x end and spreads: squares farther along strike
    rupture later (BP5's rupture-time contours)."""
    from faultslip.models.fault_3d.bp5_outputs import rupture_times

    scene = load_fault_3d_scene(SMALL)
    scene.duration = 1.0 * YEAR
    run = scene.run()
    times = scene.fault.grid(rupture_times(run, 0) - run.events["start"][0])
    row = 5  # 0.55 km down dip, in the patch
    along = times[:, row]
    finite = np.isfinite(along)
    assert finite.sum() > 20
    patch_end = scene.fault.column(-900.0)
    assert np.all(np.diff(along[patch_end:][np.isfinite(along[patch_end:])]) >= -1e-9)


@pytest.mark.parametrize("change,message", [
    (("a = { inside", "a = { within"), "BP5's patch"),
    (('length = "5 km"', 'length = "5.05 km"'), "must divide"),
    (('stations = [["0 km", "0 km"]', 'stations = [["9 km", "0 km"]'), "on the fault"),
    (('rake = "strike"', 'rake = "oblique"'), "rake"),
    (('family = "fault_3d"', 'family = "fault_2d"'), "fault_3d"),
    (('strike_to = "-0.9 km"', 'strike_to = "-2 km"'), "strike_from must lie before"),
    (('critical_slip = "7 mm"', 'critical_slip = "7 parsecs"'), "critical_slip"),
])
def test_a_bad_scene_is_one_sentence(change, message):
    text = SMALL.read_text(encoding="utf-8")
    assert change[0] in text
    with pytest.raises(InputError, match=message):
        parse_fault_3d_scene(text.replace(change[0], change[1], 1), "bad.toml")


def test_the_middle_column_is_the_2d_rung():
    """The rung below reads the same scene: the middle column's a(z), the same b, D_c, sigma_n and loading."""
    scene = load_fault_3d_scene(SMALL)
    two_d = scene.two_d()
    fault = scene.fault
    column = fault.column(0.0)
    assert two_d.count == fault.dip_count and two_d.plane == "antiplane"
    assert np.allclose(two_d.a, fault.grid(fault.a)[column])
    assert math.isclose(two_d.plate_rate, fault.plate_rate)


def _operator_in_a_child(queue):
    queue.put(float(kernel.StrikeConvolution(6, 3, 1000.0).self_term[0]))


def test_a_process_that_built_a_kernel_can_fork_workers_that_build_theirs():
    """cutde's OpenMP runtime is held to one thread: a forked worker of a process that had assembled a kernel (a sweep
    after a run in one notebook) once hung at its first dislocation."""
    import multiprocessing

    kernel.StrikeConvolution(8, 4, 1000.0)
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    child = context.Process(target=_operator_in_a_child, args=(queue,))
    child.start()
    child.join(120)
    alive = child.is_alive()
    if alive:
        child.kill()
    assert not alive, "the forked worker hung in the dislocation kernel"
    assert queue.get(timeout=5) < 0


def test_every_rung_reads_the_3d_scene_and_declares_its_model_error(cli):
    """`faultslip run SCENE --model NAME` on a 3-D scene: the one slider and the 2-D fault read its middle column,
    and each declares its own error compounded with the 2-D fault's model error against 3-D, its ranges widened to
    it; `model-error` puts the three rungs side by side."""
    from faultslip.fault import strike_error

    scene = load_fault_3d_scene(SMALL)
    model_error = strike_error.declared_for(scene.fault)
    result = cli("run", SMALL, "--model", "fault_2d", "--json")
    assert result.code == 0, result.err
    document = json.loads(result.out)
    values = document.get("results", document)
    declared = values["estimated_relative_error"]
    band = values["slip_per_event_range"]
    if math.isfinite(model_error):
        assert declared >= model_error
        if declared < 1.0:  # where the truth lies: [v / (1 + e), v / (1 - e)]
            low, high = band["value"] if isinstance(band, dict) else band
            assert low < high
        else:  # no upper bound, so no range: the error alone is declared
            assert band is None or (isinstance(band, dict) and band["value"] is None)
    else:
        assert declared is None
    ladder = cli("model-error", SMALL, "--json")
    assert ladder.code == 0, ladder.err
    text = ladder.out
    for rung in ("one_slider", "fault_2d", "fault_3d"):
        assert f"{rung}_recurrence" in text
    document = json.loads(text)
    report = document.get("results", document)
    error = report["fault_2d_declared_error"]
    error = error["value"] if isinstance(error, dict) else error
    if error is not None and error >= 1:  # a declared error with no range says why
        assert "fault_2d_recurrence_range" not in report and "fault_2d: its declared error" in text


def test_a_tolerance_no_rung_can_meet_is_refused_before_any_work(cli):
    from faultslip.models.fault_3d.family import discretisation_error

    scene = load_fault_3d_scene(SMALL)
    tolerance = 0.5 * discretisation_error(scene.resolution)
    result = cli("run", SMALL, "--tolerance", tolerance)
    assert result.code == 2 and "no rung meets" in result.err and "Traceback" not in result.err


def test_a_fault_periodic_along_strike_is_the_2d_fault():
    """The 2-D limit of the 3-D machinery: a fault periodic along strike (its kernel summed over M images either
    side), its friction the 2-D fault's on every column, steps through the 2-D fault's own events, the difference
    falling as the images' truncation does, 1 / M^2 (measured 0.74 % at M = 20, 0.095 % at 80). A finite fault does
    not reach it: its creeping ends nucleate events (docs/fault_3d.md, benchmarks/fault_3d_model_error.py)."""
    from faultslip.models.fault_3d.model import Fault3D

    scene = load_fault_3d_scene(SMALL)
    flat = scene.two_d()
    columns = 4
    tiled = {key: np.tile(getattr(flat, key), columns) for key in ("a", "b", "critical_slip", "normal_stress",
                                                                   "initial_shear_stress", "initial_state")}
    fault = Fault3D(flat.element_size, tiled["a"], tiled["b"], tiled["critical_slip"], tiled["normal_stress"],
                    flat.shear_modulus, flat.shear_wave_speed, flat.plate_rate, flat.reference_speed,
                    flat.reference_friction, tiled["initial_shear_stress"], tiled["initial_state"], plane="3d",
                    poisson_ratio=0.25, strike_count=columns, strike_origin=0.0)
    two = run_cycles(flat, 45 * YEAR, rtol=1e-8, stations=[500.0], profile_interval=YEAR)
    assert two.event_count >= 3
    errors = []
    for images in (20, 80):
        operator = kernel.StrikeConvolution(columns, flat.count, flat.element_size, 90.0, "strike",
                                            flat.shear_modulus, 0.25, periodic_images=images)
        operator.settings = {"periodic_images": images}
        three = run_cycles(fault, 45 * YEAR, rtol=1e-8, operator=operator, profile_interval=YEAR,
                           stations=StationGrid([(200.0, 500.0)], fault))
        assert three.event_count == two.event_count
        assert np.ptp(fault.grid(three.final_slip), axis=0).max() == 0.0  # uniform along strike throughout
        errors.append(np.max(np.abs(three.events["start"][1:] / two.events["start"][1:] - 1)))
    assert errors[1] < 2e-3 and errors[0] / errors[1] > 4.0


def test_the_2d_rungs_model_error_is_bounded_by_shorter_narrower_shallower_cells():
    from faultslip.fault.strike_error import declared

    rows = [{"aspect": 2.0, "burial": 0.1, "width_over_nucleation": 1.0, "model_error": 3.0},
            {"aspect": 4.0, "burial": 0.1, "width_over_nucleation": 1.0, "model_error": 1.5},
            {"aspect": 4.0, "burial": 0.3, "width_over_nucleation": 1.0, "model_error": 0.8},
            {"aspect": 8.0, "burial": 0.1, "width_over_nucleation": 1.5, "model_error": None},
            {"aspect": 16.0, "burial": 0.1, "width_over_nucleation": 2.5, "model_error": 0.5}]
    assert declared(5.0, rows, 0.2, 1.2) == 1.5  # the nearest bounding aspect, its shallower cell only
    assert declared(5.0, rows, 0.4, 1.2) == 1.5  # both cells at aspect 4 bound it: the larger
    assert declared(3.0, rows, 0.2, 1.2) == 3.0
    assert declared(1.5, rows, 0.2, 1.2) == math.inf  # shorter than every measured patch
    assert declared(5.0, rows, 0.05, 1.2) == math.inf  # shallower than every measured patch
    assert declared(9.0, rows, 0.2, 2.0) == math.inf  # its nearest bounding cell's 3-D run did not settle
    # outside the measured region: no settled cell as wide (or as long), however many shorter, narrower ones bound it
    assert declared(5.0, rows, 0.2, 2.6) == math.inf and declared(17.0, rows, 0.2, 2.5) == math.inf
    assert declared(5.0, rows[:3], 0.2, 1.2) == math.inf  # no settled cell as long: the order is not extrapolated
    assert declared(16.0, rows, 0.2, 2.5) == 0.5


def test_a_2d_scenes_fault_length_names_the_3d_model_error_or_why_none_is_declared():
    from faultslip.fault.strike_error import declared, length_note

    rows = [{"aspect": 2.0, "burial": 0.1, "width_over_nucleation": 1.0, "model_error": 3.0},
            {"aspect": 4.0, "burial": 0.1, "width_over_nucleation": 1.0, "model_error": 1.5},
            {"aspect": 8.0, "burial": 0.1, "width_over_nucleation": 1.5, "model_error": 0.9}]
    # 50 km of a 10 km patch (L / W 5), buried 0.2 W: the L / W 4 cell bounds it
    bounded = length_note(50e3, 10e3, 0.2, 1.2, rows)
    assert declared(5.0, rows, 0.2, 1.2) == 1.5 and "differ from it by up to 150%" in bounded
    assert "infinitely long along strike" in bounded
    # the same fault breaking the surface (burial 0): shallower than every measured patch, nothing declared
    surface = length_note(50e3, 10e3, 0.0, 1.2, rows)
    assert "not declared" in surface and "burial 0.1-0.1" in surface and "differ" not in surface
    # the surface-breaking patches measured near its L / W are quoted, as measurements that bound nothing
    quoted = length_note(50e3, 10e3, 0.0, 1.2, rows, [{"aspect": 4.5, "width_over_nucleation": 1.2,
                                                      "measured_error": 0.4},
                                                     {"aspect": 30.0, "width_over_nucleation": 2.5,
                                                      "measured_error": 0.9}])
    assert "were 40%-40% off" in quoted and "bounds no other fault" in quoted


def test_the_shipped_model_error_table_is_the_benchmarks_measurement_times_the_margin():
    from faultslip.fault.strike_error import MARGIN, load_table

    bench = load_benchmark("fault_3d_model_error")
    measured = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_model_error.json").read_text(encoding="utf-8"))
    shipped = load_table()
    buried = [cell for cell in measured["rows"] if cell["burial"] > 0]
    assert len(shipped["rows"]) == len(buried)
    for row, cell in zip(shipped["rows"], buried):
        assert row["aspect"] == pytest.approx(cell["aspect_measured"])
        # a cell bounds with its error times the margin where its 3-D run settled into a cycle; one that did not
        # (unsettled or aperiodic, run four times as long) bounds nothing
        assert row["model_error"] == bench.bound_of(cell)
        if cell["fault_3d"]["sequence"] == "periodic" and cell["model_error"] is not None:
            assert row["model_error"] == pytest.approx(MARGIN * cell["model_error"])
        else:
            assert row["model_error"] is None and cell["years"] >= 4 * 120.0  # run longer before it was given up
    # surface-breaking patches bound nothing: they err less than buried ones of the same L / W, so they cannot bound
    # a buried fault, and among themselves a wider one errs more than a narrower (measured, shipped apart for the reports)
    surface = [cell for cell in measured["rows"] if cell["burial"] == 0]
    assert [row["measured_error"] for row in shipped["surface_rows"]] == [cell["model_error"] for cell in surface]
    long_ones = [cell for cell in surface if cell["aspect_measured"] > 6 and cell["model_error"] is not None]
    by_width = sorted(long_ones, key=lambda cell: cell["width_over_nucleation"])
    assert by_width[-1]["model_error"] > by_width[0]["model_error"]
    held = measured["held_out"]
    assert not any(r["declared"] is not None and not r["covered"] for r in held)
    assert all(r["declared"] is None for r in held if r["burial"] == 0)


def test_the_fresh_strike_draws_hold_the_shipped_declaration():
    """benchmarks/results/fault_3d_model_error_fresh.json (fault_3d_model_error.py --fresh): buried patches drawn
    after the table was shipped, each as FRESH_DRAWS names it (the same draw of inputs), its model error the runs'
    own and its bound what the library declares now; none lies outside a declared bound."""
    from faultslip.fault.strike_error import declared, load_table

    bench = load_benchmark("fault_3d_model_error")
    recorded = json.loads(bench.FRESH_OUT.read_text(encoding="utf-8"))
    assert [(draw["seed"], len(draw["rows"]), draw["box"]) for draw in recorded["draws"]] == list(bench.FRESH_DRAWS)
    rows = load_table()["rows"]
    for draw in recorded["draws"]:
        rng = np.random.default_rng(draw["seed"])
        for row in draw["rows"]:
            drawn = bench.DRAWS[draw["box"]](rng, row["element_size_m"])
            assert (row["aspect"], row["height_m"], row["top_m"]) == drawn
            assert row == bench.judged(bench.with_model_error(row), rows)
            bound = declared(row["aspect_measured"], rows, row["burial"], row["width_over_nucleation"])
            assert row["declared"] is None or row["declared"] == pytest.approx(bound)
            assert row["covered"] or row["declared"] is None  # unbounded is said; a bound is never exceeded


def _read_again(side: dict, tolerance: float) -> tuple:
    """A recorded side of a model-error cell read again from its system-size events, as faultslip.run reads a run
    (faultslip.models.fault_2d.analysis.unsettled_window): its kind, recurrence (yr) and mean slip (m)."""
    from faultslip.models.fault_2d.analysis import classify, unsettled_window

    intervals = np.asarray(side["intervals_yr"], float) * YEAR
    sequence = unsettled_window(classify(intervals, tolerance), intervals)
    window = np.asarray(side["system_slip_m"], float)[sequence.first_event:]
    closing = window[1:] if window.size > 1 else window
    return sequence.kind, sequence.mean_interval / YEAR, float(closing.mean())


def test_the_model_error_cells_read_an_unsettled_run_as_a_run_does():
    """Every cell of benchmarks/fault_3d_model_error.py (calibration, held out and the fresh draws) records each
    rung's answer as faultslip.run reports it: read again here from the system-size events' intervals and slips the
    row keeps, an unsettled run over its intervals after the first, not its last alone (the reading before the
    table was measured again). Both tolerances are the families' own."""
    from faultslip.models.fault_2d import family as fault_2d_family
    from faultslip.models.fault_3d import family as fault_3d_family

    bench = load_benchmark("fault_3d_model_error")
    measured = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_model_error.json").read_text(encoding="utf-8"))
    fresh = json.loads(bench.FRESH_OUT.read_text(encoding="utf-8"))
    rows = measured["rows"] + measured["held_out"] + [row for draw in fresh["draws"] for row in draw["rows"]]
    tolerances = {"fault_3d": fault_3d_family.SETTLE_TOLERANCE, "fault_2d": fault_2d_family.SETTLE_TOLERANCE}
    windowed = 0
    for row in rows:
        for rung, tolerance in tolerances.items():
            side = row[rung]
            kind, recurrence, slip = _read_again(side, tolerance)
            assert kind == side["sequence"], (row["aspect"], row["height_m"], rung)
            assert (recurrence == pytest.approx(side["recurrence_yr"], rel=1e-12)
                    or math.isnan(recurrence) and math.isnan(side["recurrence_yr"])), (row["aspect"], rung)
            assert slip == pytest.approx(side["mean_slip_m"], rel=1e-9), (row["aspect"], row["height_m"], rung)
            windowed += kind == "unsettled" and len(side["intervals_yr"]) >= 3
    assert windowed >= 5  # the reading that changed is exercised, not only settled rows


def test_the_3d_starts_file_is_its_runs():
    """benchmarks/results/fault_3d_starts.json (fault_3d_model_error.py --starts): each cell's run from its own start
    is the recorded 3-D run of that cell, each start's recurrence change is the runs' own, and the summary
    docs/fault_3d.md quotes is recomputed from the cells."""
    from conftest import load_benchmark

    from faultslip.fault.starts import START_FACTORS

    bench = load_benchmark("fault_3d_model_error")
    starts = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_starts.json").read_text(encoding="utf-8"))
    measured = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_model_error.json").read_text(encoding="utf-8"))
    recorded = {bench._key(row): row for row in measured["rows"] + measured["held_out"]}
    assert len(starts["cells"]) == len(recorded)
    for cell in starts["cells"]:
        row = recorded[bench._key(cell)]
        own = cell["recurrence_yr"][0]
        assert (own == row["fault_3d"]["recurrence_yr"]) or (math.isnan(own) and math.isnan(row["fault_3d"]["recurrence_yr"]))
        assert cell["start_speeds"][1:] == pytest.approx([f * cell["start_speeds"][0] for f in START_FACTORS])
        if all(map(math.isfinite, cell["recurrence_yr"])):
            changes = [t / own - 1 for t in cell["recurrence_yr"][1:]]
            assert cell["start_change"] == pytest.approx(max(changes, key=abs))
        else:
            assert cell["multistable"] is None or cell["multistable"] is True
    assert starts["summary"] == bench.starts_summary(starts["cells"])


def test_an_event_under_way_at_the_start_starts_at_zero():
    """BP5's nucleation patch slips at 1 cm/s from t = 0: the first event starts then, not before."""
    scene = load_fault_3d_scene(SMALL)
    scene.duration = 0.2 * YEAR
    run = scene.run()
    assert run.event_count >= 1 and run.events["start"][0] == 0.0


@pytest.mark.parametrize("dip,rake", [(90.0, "strike"), (60.0, "thrust")])
def test_the_cross_rake_traction_is_each_squares_own(dip, rake):
    """The traction across the rake (what a second slip component would answer) of one square's slip equals that
    square's dislocations evaluated at every centre; on a vertical strike-slip fault it is odd along strike."""
    strike_count, dip_count, h = 7, 4, 1000.0
    operator = kernel.StrikeConvolution(strike_count, dip_count, h, dip, rake, G, 0.25)
    source = 3 * dip_count + 1  # square (3, 1): the middle column
    slip = np.zeros(strike_count * dip_count)
    slip[source] = 1.0
    tris = kernel.element_triangles(np.array([3 * h]), np.array([1 * h]), h, dip)
    index_strike, index_dip = np.divmod(np.arange(strike_count * dip_count), dip_count)
    _, _, expected = kernel.tractions(kernel.centres(index_strike, index_dip, h, dip), tris,
                                      kernel._tdcs_slip(tris, kernel.slip_direction(rake, dip)), dip, rake, G, 0.25)
    cross = operator.cross(slip)
    assert np.max(np.abs(cross - expected)) <= 1e-9 * np.max(np.abs(expected))
    if dip == 90.0 and rake == "strike":
        grid = cross.reshape(strike_count, dip_count)
        assert np.allclose(grid[:3], -grid[4:][::-1], atol=1e-6 * np.max(np.abs(grid)))


def test_the_declared_resolution_error_holds_on_bp5_at_every_size():
    """BP5-QD at 2000, 1000 and 500 m (benchmarks/seas_bp5.py's saved runs): the family's declared error bounds
    each size's interval against the finest and against tandem's, and the constants are the benchmark's fit,
    rounded up."""
    from faultslip.models.fault_3d.family import DISCRETISATION, discretisation_error

    result = json.loads((ROOT / "benchmarks" / "results" / "seas_bp5.json").read_text(encoding="utf-8"))
    fit = result["fit"]
    assert DISCRETISATION["margin"] * DISCRETISATION["scale"] >= fit["margin"] * fit["scale"]
    assert DISCRETISATION["order"] <= fit["order"] + 1e-9
    for run in result["runs"]:
        declared = discretisation_error(run["resolution"])
        assert abs(run["interval_difference_from_finest"]) <= declared, run["element_size_m"]
        assert abs(run["interval_difference_from_tandem"]) <= declared, run["element_size_m"]



def test_the_declared_resolution_error_holds_on_drawn_faults_it_was_not_fitted_on():
    """benchmarks/results/fault_3d_resolution.json (fault_3d_resolution.py): faults drawn over the held-out box, each
    run at 100, 50 and 25 m squares through faultslip.run. Each run's declared error is the square size's bound
    (as declared now) plus the sequence's and 10 rtol (as it declared them); each coarser run's recurrence lies
    within its and the finest run's declared errors added of the finest (its own, where three sizes give a
    Richardson limit). The margin on BP5's fit is the least that covers every drawn run, rounded up to a tenth
    (recomputed here: a drawn fault that needs more fails), and more than BP5's 2, which one unsettled fault
    exceeded. The cost model's estimate is within 2x of the CPU each run used."""
    from faultslip.models.fault_3d.family import DISCRETISATION, discretisation_error

    bench = load_benchmark("fault_3d_resolution")
    result = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_resolution.json").read_text(encoding="utf-8"))
    assert result["fault_count"] >= 8 and all(len(fault["sizes_m"]) == 3 for fault in result["judged"])
    needed = bench.margin_needed(result["judged"])
    assert needed == pytest.approx(result["margin_needed"]) and needed > 2.0
    assert needed <= DISCRETISATION["margin"] <= math.ceil(needed * 10) / 10
    for fault in result["judged"]:
        finest = fault["runs"][f"{min(fault['sizes_m']):g}"]
        for row in fault["errors"]:
            run = fault["runs"][f"{row['element_size_m']:g}"]
            declared = bench.declared_now(run)
            assert declared == pytest.approx(run["declared"] - run["discretisation_error"]
                                             + discretisation_error(run["resolution"]))
            assert run["declared"] >= run["discretisation_error"] and declared >= discretisation_error(
                run["resolution"]) - 1e-12, (fault["name"], row)
            if row["error_recurrence"] is None:
                continue
            allowed = declared + (0.0 if fault["richardson_recurrence"] else bench.declared_now(finest))
            assert math.isclose(row["allowed"], allowed) and row["error_recurrence"] <= allowed, (fault["name"], row)
        for run in fault["runs"].values():
            assert 0.5 <= run["estimated_cpu_s"] / run["cpu_time_s"] <= 2.0, (fault["name"], run["element_size_m"])


@pytest.mark.parametrize("name", ["fault_3d_resolution_fresh.json", "fault_3d_resolution_fresh_second.json"])
def test_the_recurrence_bounds_margin_holds_on_faults_drawn_after_it_was_set(name):
    """benchmarks/results/fault_3d_resolution_fresh.json (fault_3d_resolution.py --seed 7403 --out ...) and
    fault_3d_resolution_fresh_second.json (seed 7405, sessions later): faults drawn with another seed after the
    margin was set from fault_3d_resolution.json's, never part of it, each run at 100, 50 and 25 m. Judged again
    here with the bound as declared now (so a changed bound without a rerun is read afresh), each coarser run's
    recurrence and slip per event lie within what it may differ by, and the least margin these faults need is
    within the declared one. The cost estimate is within 2x of the CPU used."""
    from faultslip.models.fault_3d.family import DISCRETISATION

    bench = load_benchmark("fault_3d_resolution")
    result = json.loads((ROOT / "benchmarks" / "results" / name).read_text(encoding="utf-8"))
    fitted = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_resolution.json").read_text(encoding="utf-8"))
    first = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_resolution_fresh.json").read_text(
        encoding="utf-8"))
    assert result["seed"] != fitted["seed"] and result["fault_count"] >= 5
    assert name == "fault_3d_resolution_fresh.json" or result["seed"] != first["seed"]
    drawn = {"aspect", "height_m", "top_m", "critical_slip_factor"}
    assert not ({tuple(fault[k] for k in sorted(drawn)) for fault in result["judged"]}
                & {tuple(fault[k] for k in sorted(drawn)) for fault in fitted["judged"]})
    judged = [bench.judged({key: fault[key] for key in drawn | {"name", "runs"}}) for fault in result["judged"]]
    assert all(fault["sizes_m"] == [100.0, 50.0, 25.0] for fault in judged)
    assert bench.margin_needed(judged) <= DISCRETISATION["margin"]
    for fault in judged:
        assert None not in (fault["errors"][0]["error_recurrence"], fault["errors"][0]["error_slip"])
        for row in fault["errors"]:  # the finest too, where three sizes give a Richardson limit
            assert row["error_recurrence"] is None or row["holds"], (fault["name"], row)
            assert row["error_slip"] is None or row["holds_slip"], (fault["name"], row)
        for run in fault["runs"].values():
            assert 0.5 <= run["estimated_cpu_s"] / run["cpu_time_s"] <= 2.0, (fault["name"], run["element_size_m"])


def test_the_cost_model_is_its_benchmarks_fit_and_estimates_unseen_faults_within_2x():
    """The cost model is benchmarks/fault_3d_cost.py's fit, refitted here from its results file: the steps
    (least squares in ln steps on ln events, ln W / h*, ln N_x, the burial and ln squares per L_b, over its fit
    runs, the model-error benchmark's cells and the resolution benchmark's draw; its held-out faults, never
    fitted, within 0.75-1.33x and closer with the squares per L_b than without) and the CPU a step (relative
    non-negative least squares on 1, N and k (N_x + 1) N_z^2 over its fit runs). What each run's estimate read
    is what it reads now, and on the held-out draw, run after the model was chosen and never part of the fit,
    the shipped model's estimate (recomputed here, so a changed model without a rerun fails) is within 2x of the
    CPU used. The earlier draws keep the estimates of their day's model (the second found a buried patch at
    2.96x) and record the shipped model's, recomputed here too; the fresh draws, each estimated by the model it ran
    after, hold 95 % of their estimates within 2x."""
    from faultslip.io import machine
    from faultslip.models.fault_3d import cost

    bench = load_benchmark("fault_3d_cost")
    result = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_cost.json").read_text(encoding="utf-8"))
    # the model-error cells' steps are those fault_3d_model_error.json records now (a rerun of its cells that the
    # cost file's copy predates fails here: --part re-estimate copies them again)
    recorded = bench.recorded_cells()
    assert len(result["recorded_cells"]) == len(recorded)
    for kept, now in zip(result["recorded_cells"], recorded):
        assert kept.keys() == now.keys() and all(kept[key] == pytest.approx(now[key], rel=1e-9) if isinstance(
            now[key], float) else kept[key] == now[key] for key in now), (kept, now)
    # and the resolution benchmark's runs (the fitted draw and its held-out faults) are what its file records now
    for kept, now in ((result["resolution_runs"], bench.resolution_runs()),
                      (result["resolution_held_out_runs"], bench.resolution_runs(bench.RESOLUTION_HELD_OUT))):
        assert len(kept) == len(now) >= 15 and {row["resolution"] > 9.0 for row in now} == {True, False}
        for row, again in zip(kept, now):
            assert row.keys() == again.keys() and all(row[key] == pytest.approx(again[key], rel=1e-9) if isinstance(
                again[key], float) else row[key] == again[key] for key in again), (row, again)
    fitted_rows = result["fit_runs"] + result["recorded_cells"] + result["resolution_runs"]
    steps = bench.fit_steps(fitted_rows)
    for name in ("events", "width_over_nucleation", "strike_columns", "burial", "resolution"):
        assert cost.FAULT_3D_STEPS[name] == pytest.approx(steps[name], abs=0.01), name
    assert cost.FAULT_3D_STEPS["scale"] == pytest.approx(steps["scale"], rel=0.01)
    # a central estimate: every fitted run's steps within 2x of it; the burial narrows the residuals
    assert 0.5 <= steps["residual_range"][0] and steps["residual_range"][1] <= 2.0
    without = bench.fit_steps(fitted_rows, burial=False, resolution=False)
    assert steps["residual_sd"] < 0.75 * without["residual_sd"]
    # finer squares take more steps (R^s, s > 0); on the faults it never fitted, the term narrows the estimate
    assert steps["resolution"] > 0.1
    held_out = bench.steps_over_measured(result["resolution_held_out_runs"])  # the shipped model's
    assert held_out["count"] >= 15 and 0.75 <= held_out["range"][0] and held_out["range"][1] <= 1.33, held_out
    before = bench.steps_over_measured(result["resolution_held_out_runs"],
                                       bench.fit_steps(fitted_rows, resolution=False))
    assert held_out["sd_ln"] < before["sd_ln"] and abs(math.log(held_out["median"])) < abs(math.log(before["median"]))
    # the burial and the squares per L_b are held to the fitted runs' ranges: past them nothing is extrapolated
    fitted_burial = max(row["burial"] for row in fitted_rows)
    assert cost.FAULT_3D_STEPS["burial_fitted"] == pytest.approx(fitted_burial, abs=1e-3)
    assert cost.steps(40, 10.0, 1.3, 1e-6, burial=3.0) == cost.steps(40, 10.0, 1.3, 1e-6, burial=fitted_burial)
    lowest, highest = cost.FAULT_3D_STEPS["resolution_fitted"]
    assert (lowest, highest) == pytest.approx(steps["resolution_fitted"], rel=1e-3)
    assert cost.steps(40, 10.0, 1.3, 1e-6, resolution=40.0) == cost.steps(40, 10.0, 1.3, 1e-6, resolution=highest)
    assert cost.steps(40, 10.0, 1.3, 1e-6, resolution=1.0) == cost.steps(40, 10.0, 1.3, 1e-6, resolution=lowest)
    # the rtol power, the 2-D fault's, is the 3-D fault's measured one within 0.03 (7 % in steps a decade of rtol)
    rtol = bench.fit_rtol(result["rtol_runs"])
    assert len(result["rtol_runs"]) >= 12 and abs(rtol["power"] - cost.FAULT_3D_STEPS["rtol"]) <= 0.03
    assert all(abs(power - cost.FAULT_3D_STEPS["rtol"]) <= 0.04 for power in rtol["per_fault"].values())
    fitted = bench.fit_step_seconds(result["fit_runs"])["coefficients"]
    assert np.allclose(cost.FAULT_3D_STEP_SECONDS, fitted, rtol=0.01, atol=1e-12)
    assert any(row["products"] == 2 for row in result["fit_runs"])  # a dipping fault's step is measured
    draws = dict(bench.held_out_draw(result["held_out_seed"]))
    assert len(result["held_out"]) >= 10
    for row in result["held_out"]:
        scene = draws[row["what"]]()
        for name, value in bench.features(scene).items():
            assert row[name] == pytest.approx(value, rel=1e-9), (row["what"], name)
        # on the machine the costs were anchored on (faultslip.io.machine; a row before it was estimated there)
        anchored = row.get("estimated_anchored_s", row["estimated_s"])
        assert scene.estimate().seconds == pytest.approx(anchored, rel=1e-6), row["what"]
        assert 0.5 <= row["estimated_s"] / row["cpu_s"] <= 2.0, row["what"]
    kinds = {row["what"].split()[0] for row in result["held_out"]}
    assert {"patch", "BP5", "fault_2d_surface_small", "fault_2d_small", "fault_2d_dipping_small"} <= kinds
    assert result["held_out_seed"] not in bench.EARLIER_DRAWS
    for draw in result["earlier_draws"]:
        made = dict(bench.held_out_draw(draw["seed"]))
        for row in draw["rows"]:
            with machine.assumed(row["machine_factor"]):
                assert made[row["what"]]().estimate().seconds == pytest.approx(row["estimated_now_s"], rel=1e-6)
    # the fresh draws, each run after the model it was estimated by: each estimate the shipped model's, and 95 % of
    # them within 2x of the CPU used. Every row of the first four draws was; draw 7329 has one miss at 2.15x, a patch
    # at W / h* 1.03, near the stability boundary, that ruptured once in 120 yr where the estimate expected 19.7
    # events (docs/fault_3d.md names it); draw 7331, the first estimated with the machine speed record, has none
    assert {draw["seed"] for draw in result["fresh_draws"]} == set(bench.FRESH_DRAWS)
    ratios = []
    for draw in result["fresh_draws"]:
        assert draw["seed"] not in (result["held_out_seed"], *bench.EARLIER_DRAWS)
        made = dict(bench.held_out_draw(draw["seed"]))
        assert len(draw["rows"]) >= 10
        for row in draw["rows"]:
            ratios.append(row["estimate_over_cpu"])
            with machine.assumed(row["machine_factor"]):
                assert made[row["what"]]().estimate().seconds == pytest.approx(row["estimated_now_s"], rel=1e-6)
    assert sum(0.5 <= ratio <= 2.0 for ratio in ratios) >= 0.95 * len(ratios), sorted(ratios)


def test_the_assembly_cost_is_the_cost_benchmarks_and_the_product_is_exact():
    """Seconds per (triangle, observation) pair: the median over benchmarks/fault_3d_cost.py's fit runs that spent a
    second or more assembling (their CPU, timed apart from the steps), refitted here; the FFT product equals the
    dense one to round-off (benchmarks/fault_3d_operator.py)."""
    from faultslip.models.fault_3d import cost

    fitted = load_benchmark("fault_3d_cost").fit_assembly(json.loads(
        (ROOT / "benchmarks" / "results" / "fault_3d_cost.json").read_text(encoding="utf-8"))["fit_runs"])
    assert fitted["runs"] >= 4
    assert cost.FAULT_3D_PAIR_SECONDS == pytest.approx(fitted["pair_seconds"], rel=0.01)
    result = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_operator.json").read_text(encoding="utf-8"))
    assert result["largest_relative_error"] <= 1e-12  # the FFT product is exact (issue: <= 1e-6 asked)


def test_a_declared_error_ranges_where_the_truth_lies():
    """One inversion for every rung's range (faultslip.fault.ladder.truth_range), the 3-D family's among them."""
    from faultslip.fault import ladder
    from faultslip.models.fault_3d import family

    assert family.truth_range is ladder.truth_range
    assert ladder.truth_range(100.0, 0.25) == pytest.approx([80.0, 100.0 / 0.75])
    assert ladder.truth_range(100.0, 1.0) is None and ladder.truth_range(100.0, None) is None


def test_check_starts_runs_the_3d_fault_from_other_starts(cli):
    """--check-starts on the 3-D rung (through faultslip.fault.starts, as the 2-D rung): the small BP5 scene from
    its start and from 0.1 and 10 times its background slip rate (its nucleation patch kept) settles to one
    periodic cycle; the three runs are budgeted together; a lower rung or a tolerance is refused in one sentence."""
    from faultslip.models import estimate

    done = cli("run", SMALL, "--check-starts", "--json")
    assert done.code == 0, done.err
    document = json.loads(done.out)
    report = document.get("results", document)
    recurrences = report["start_recurrences"]["value"]
    assert recurrences[0] == report["recurrence_interval"]["value"]
    assert report["start_sequences"] == ["periodic"] * 3
    assert report["multistable"] is False and abs(report["start_change"]) <= 0.01
    scene = load_fault_3d_scene(SMALL)
    three = estimate(SMALL, "run", check_starts=True)
    assert three.seconds == pytest.approx(scene.estimate(in_this_process=True).seconds + sum(
        s.estimate().seconds for s in (scene.from_start(1e-10), scene.from_start(1e-8))))
    for extra in (("--model", "fault_2d"), ("--tolerance", "0.5")):
        refused = cli("run", SMALL, "--check-starts", *extra)
        assert refused.code == 2 and "--model fault_3d" in refused.err and len(refused.err.strip().splitlines()) == 1


#: A 2-D scene whose 3-D fault runs in seconds: BP5's friction at 1/20 (configs/fault_3d_small.toml's) down dip to
#: the surface, 2.8 elements per L_b, W / h* near 1.2, read as a fault 3 km long.
TINY_2D = (ROOT / "configs" / "fault_2d_surface_small.toml").read_text(encoding="utf-8")


def test_a_2d_scenes_3d_fault_is_its_profile_on_every_column_of_its_length(tmp_path):
    """The 3-D rung of a 2-D scene: within fault_length / 2 of the middle every column is the 2-D fault (friction
    and start, bit for bit); beyond the ends, past the profile's own ramp, every square has the profile's largest
    a (strengthening: a > b); the domain reaches the ramp and a rupture zone's width beyond each end."""
    from faultslip.fault.ladder import groups
    from faultslip.models.fault_2d.scene import read_fault_2d_scene
    from faultslip.models.fault_3d.scene import from_two_d

    (tmp_path / "tiny.toml").write_text(TINY_2D)
    flat = read_fault_2d_scene(tmp_path / "tiny.toml")
    scene = from_two_d(flat)
    fault, two = scene.fault, flat.fault
    along = (np.arange(fault.strike_count) + 0.5) * fault.element_size + fault.strike_origin
    inside = np.abs(along) <= flat.fault_length / 2
    zone = groups(two.description())
    ramp = max(zone["ramp"] * zone["width"], 2 * two.element_size)
    for key in ("a", "b", "critical_slip", "normal_stress", "initial_shear_stress", "initial_state"):
        grid = fault.grid(getattr(fault, key))
        assert np.array_equal(grid[inside], np.broadcast_to(getattr(two, key), grid[inside].shape)), key
    beyond = np.abs(along) >= flat.fault_length / 2 + ramp
    assert beyond.sum() >= 2 and np.all(fault.grid(fault.a)[beyond] == two.a.max())
    assert np.all(fault.grid(fault.a)[beyond] > fault.grid(fault.b)[beyond])
    assert fault.strike_count * fault.element_size >= flat.fault_length + 2 * (ramp + zone["width"])
    assert scene.stations == ((0.0, 0.0), (0.0, 500.0)) and scene.duration == flat.duration
    assert scene.two_d() is two


def test_the_3d_rung_of_a_2d_scene_recurs_sooner_and_slips_less(cli, tmp_path):
    """`run SCENE --model fault_3d` reads a 2-D scene as a fault its fault_length long: a finite patch is stiffer
    than the infinitely long one (its stress drop spread over a shorter rupture) and its creeping ends load it, so
    it slips less per event and recurs sooner (here 3 km of a 0.8 km zone: measured 14 against 20 yr, 0.33 against
    0.54 m). `model-error --include-3d` puts it above the 2-D rung, every rung's slip the zone's mean."""
    path = tmp_path / "tiny.toml"
    path.write_text(TINY_2D)
    ladder = cli("model-error", path, "--include-3d", "--json")
    assert ladder.code == 0, ladder.err
    values = ladder.json
    flat = cli("run", path, "--model", "fault_2d", "--json").json
    assert values["fault_2d_slip_per_event"]["value"] == pytest.approx(flat["mean_slip_per_event"]["value"])
    assert values["fault_3d_recurrence"]["value"] < 0.9 * values["fault_2d_recurrence"]["value"]
    assert values["fault_3d_slip_per_event"]["value"] < 0.9 * values["fault_2d_slip_per_event"]["value"]
    assert "fault_2d_off_recurrence" in values
    three = cli("run", path, "--model", "fault_3d", "--json")
    assert three.code == 0, three.err
    assert three.json["method"] == "fault_3d" and "the 2-D scene small surface-breaking" in three.json["method_reason"]
    assert three.json["recurrence_interval"] == values["fault_3d_recurrence"]


def test_a_2d_scenes_3d_rung_is_refused_in_one_sentence_where_it_cannot_run(cli, tmp_path, monkeypatch):
    """BP1's scene read as a fault 100 km long needs 3,398,000 squares on its 40 m elements: refused before any
    work, naming --allow-large; a 2-D scene without a fault_length has no 3-D fault; --include-3d on a scene with no
    2-D ladder is refused; the estimate of the 3-D rung is the 3-D fault's."""
    from conftest import assert_clean_error

    configs = ROOT / "configs"
    assert_clean_error(cli("run", configs / "rsf_fault_bp1.toml", "--model", "fault_3d"), "3398000 squares",
                       "--allow-large")
    path = tmp_path / "endless.toml"
    path.write_text(TINY_2D.replace('fault_length = "3 km"\n', ""))
    assert_clean_error(cli("run", path, "--model", "fault_3d"), "states no [run] fault_length")
    assert_clean_error(cli("model-error", path, "--include-3d"), "no 3-D rung")
    assert_clean_error(cli("model-error", configs / "rsf_block_bp1.toml", "--include-3d"), "--include-3d")
    # BP1's ladder with its 3-D rung is refused before its 2-D rung runs (the model-error call returns at once)
    from faultslip.models.fault_2d import family

    ran = []
    monkeypatch.setattr(family, "simulate_fault", lambda *args, **kwargs: ran.append(args))
    assert_clean_error(cli("model-error", configs / "rsf_fault_bp1.toml", "--include-3d"), "the 3-D rung (",
                       "--allow-large")
    assert not ran
    estimate = cli("run", configs / "fault_2d_small.toml", "--model", "fault_3d", "--estimate", "--json")
    assert estimate.code == 0 and "a 3-D fault run of 282 x 80 squares" in estimate.out


@pytest.mark.parametrize("surface", ["none", [{"aspect": "7"}], [{"aspect": 7.0, "width_over_nucleation": 1.2,
                                                                   "measured_error": -0.4}]])
def test_a_strike_table_with_malformed_surface_rows_is_one_sentence(surface, monkeypatch):
    from faultslip.fault import strike_error

    rows = [{"aspect": 2.0, "burial": 0.1, "width_over_nucleation": 1.0, "model_error": 3.0}]
    monkeypatch.setattr(strike_error, "read_bundled_table", lambda *args: {"rows": rows, "surface_rows": surface})
    strike_error.load_table.cache_clear()
    try:
        with pytest.raises(InputError, match="surface_rows lack"):
            strike_error.load_table()
    finally:
        strike_error.load_table.cache_clear()


def test_an_estimate_is_of_the_rung_run_goes_to(cli):
    """'faultslip run SMALL --model fault_2d --estimate' estimated the 3-D run (50 x 20 squares, 4.9 s) for a run
    of the 2-D middle column (20 elements, 2.3 s of CPU): the 3-D family's estimate ignored the rung. It is now the
    rung's own cost model, the one slider's or the middle column's 2-D fault's; for a tolerance, the rung
    tolerance_plan chooses, which run follows; what run refuses, it refuses."""
    from faultslip.models.fault_2d.family import one_slider_estimate
    from faultslip.models.fault_3d.family import tolerance_plan, two_d_scene

    scene = load_fault_3d_scene(SMALL)
    below = two_d_scene(scene)
    flat = faultslip.models.estimate(SMALL, method="fault_2d")
    # the cost model's seconds alone: the imports an estimate times depend on the tests this process ran before
    assert flat.modelled_seconds == pytest.approx(
        below.estimate(below.rtol, None, in_this_process=True).modelled_seconds, rel=1e-12)
    assert f"{below.fault.count} elements" in flat.what
    assert faultslip.models.estimate(SMALL, method="one_slider").modelled_seconds == pytest.approx(
        one_slider_estimate("x").modelled_seconds, rel=1e-12)
    assert faultslip.models.estimate(SMALL).modelled_seconds == pytest.approx(
        scene.estimate(in_this_process=True).modelled_seconds, rel=1e-12)
    # the small patch's 2-D model error (above 100 %) leaves the lower rungs nothing to meet: the 3-D fault runs
    plan = tolerance_plan(scene, 0.9)
    assert plan.rungs == ("fault_3d",)
    assert faultslip.models.estimate(SMALL, tolerance=0.9).modelled_seconds == pytest.approx(
        scene.estimate(in_this_process=True).modelled_seconds, rel=1e-12)
    for args, needle in ((("--model", "bogus"), "runs on one of"), (("--tolerance", "1e-9"), "no rung meets"),
                         (("--model", "fault_3d", "--tolerance", "1e-9"), "cannot meet"),
                         (("--model", "fault_2d", "--check-starts"), "--check-starts")):
        for extra in ((), ("--estimate",)):
            result = cli("run", SMALL, *args, *extra)
            assert result.code == 2 and needle in result.err and "Traceback" not in result.err, (args, extra)


def test_a_tolerance_the_2d_rung_can_meet_runs_it_first(monkeypatch):
    """Where the 2-D fault's model error against 3-D and its own least error, compounded, meet the tolerance, the
    plan tries the middle column's 2-D fault before the 3-D one, and the estimate is the 2-D run's, naming what the
    3-D fault would add if the 2-D answer misses. The shipped patches all err 39 % or more, so the model error is
    stood in for."""
    from faultslip.fault import strike_error
    from faultslip.models.fault_3d import family

    scene = load_fault_3d_scene(SMALL)
    monkeypatch.setattr(strike_error, "declared_for", lambda fault: 0.05)
    # the middle column resolves L_b about 3 times, where one 2-D run's kind-change term alone declares over 100 %:
    # stood in for by a resolved run's
    from faultslip.models.fault_2d import family as fault_2d_family
    monkeypatch.setattr(fault_2d_family, "single_run_error", lambda resolution: 0.1)
    plan = family.tolerance_plan(scene, 0.2)
    assert plan.rungs == ("fault_2d", "fault_3d")
    estimate = faultslip.models.estimate(SMALL, tolerance=0.2)
    below = family.two_d_scene(scene)
    assert estimate.seconds == below.estimate(below.rtol, None, in_this_process=True).seconds
    assert "the 3-D fault runs after it" in estimate.what
    # the small patch's middle column lies outside the one slider's box (no declared error): one inside it, whose
    # error compounded with the model error meets the tolerance, stops at the one slider
    assert plan.slider_error is None
    monkeypatch.setattr(family, "declared_error", lambda fault: 0.3)
    slider = family.tolerance_plan(scene, 0.4)
    assert slider.rungs == ("one_slider",) and slider.slider_error == pytest.approx(1.3 * 1.05 - 1)
    assert "meets the tolerance 0.4" in faultslip.models.estimate(SMALL, tolerance=0.4).what


def test_slip_sequence_error_reads_slips_as_the_recurrence_reads_intervals():
    """A period-p sequence: the largest change of a slip a supercycle later over the last 3p, over their mean; an
    unsettled one: the largest deviation of the measured events' slips about their mean (the range of the last
    three where only one is measured); too few events: infinite; an aperiodic one: the 95 % half-width of the
    measured events' mean."""
    from faultslip.intervals import correlated_mean_half_width
    from faultslip.models.fault_2d.analysis import Sequence
    from faultslip.models.fault_3d.family import slip_sequence_error

    def sequence(kind, period, first_event=0):
        return Sequence(kind, period, np.ones(1), 1.0, 0.0, 0.0, first_event)

    periodic = [0.5, 0.9, 1.0, 1.0, 1.002]
    assert slip_sequence_error(periodic, sequence("periodic", 1)) == pytest.approx(0.002 / (3.002 / 3))
    supercycle = [9.0, 1.0, 2.0, 1.0, 2.0, 1.0, 2.5]
    assert slip_sequence_error(supercycle, sequence("periodic", 2)) == pytest.approx(0.5 / (9.5 / 6))
    assert slip_sequence_error([1.0, 2.0], sequence("periodic", 2)) == math.inf
    # unsettled, measured after the spin-up (unsettled_window): the largest deviation about the measured mean
    assert slip_sequence_error([5.0, 1.0, 2.0, 3.0, 4.0], sequence("unsettled", 0, first_event=1)) == \
        pytest.approx(1.0 / 3.0)
    # too few intervals to measure: the last event stands for it, and the last three's range is its error
    assert slip_sequence_error([5.0, 1.0, 3.0], sequence("unsettled", 0, first_event=1)) == pytest.approx(4.0 / 3.0)
    assert slip_sequence_error([1.0], sequence("unsettled", 0)) == math.inf
    assert slip_sequence_error([0.0, 0.0, 0.0], sequence("periodic", 1)) == math.inf  # no 0 / 0
    rng = np.random.default_rng(3)
    slips = 1.0 + 0.1 * rng.standard_normal(40)
    measured = slips[9:]
    assert slip_sequence_error(slips, sequence("aperiodic", 0, first_event=8)) == pytest.approx(
        correlated_mean_half_width(measured) / measured.mean())


def test_an_unsettled_3d_run_reads_its_intervals_after_the_spin_up_as_the_2d_fault_does():
    """Three or more intervals, unsettled: the mean of those after the first and their largest deviation about it,
    not the last interval alone (which can lie anywhere in their range); fewer, or settled: as classified."""
    from faultslip.models.fault_2d.analysis import classify
    from faultslip.models.fault_2d.analysis import unsettled_window

    intervals = np.array([30.0, 9.0, 12.0, 8.0, 11.0])
    sequence = unsettled_window(classify(intervals), intervals)
    assert sequence.kind == "unsettled" and sequence.first_event == 1
    assert sequence.mean_interval == pytest.approx(10.0) and sequence.mean_error == pytest.approx(0.2)
    assert list(sequence.intervals) == [9.0, 12.0, 8.0, 11.0]
    short = np.array([30.0, 9.0])
    assert unsettled_window(classify(short), short) == classify(short)
    periodic = np.full(6, 10.0)
    assert unsettled_window(classify(periodic), periodic) == classify(periodic)


def test_a_study_cell_of_an_unsettled_3d_fault_reads_it_as_a_run_does():
    """A swept cell holds what faultslip.run reports for its scene (summarise as family._result calls it): of an
    unsettled sequence the mean of the intervals after the first and the mean slip of the events closing them,
    not the last interval and event."""
    from types import SimpleNamespace

    from faultslip.models.fault_3d.family import Fault3DCells

    starts = np.array([0.0, 30.0, 39.0, 51.0, 59.0, 70.0]) * YEAR  # intervals 30, 9, 12, 8, 11 yr: no period
    size = np.array([4.0, 5.0, 4.5, 6.0, 5.5, 4.8])  # every event system-size
    slip = np.column_stack([size, size, 0.5 * size])
    fault = SimpleNamespace(a=np.array([0.01, 0.01, 0.03]), b=np.array([0.02, 0.02, 0.02]), shear_modulus=3e10,
                            element_size=100.0)
    run = SimpleNamespace(fault=fault, steps=1000, event_count=6, events={"start": starts, "slip": slip})
    scene = SimpleNamespace(run=lambda: run)
    scene.with_values = lambda **_: scene
    row = Fault3DCells().evaluate(SimpleNamespace(scene=scene), {"critical_slip": np.array([0.01])})
    reported = summarise(run, unsettled_mean=True)
    assert reported["sequence"].kind == "unsettled"
    assert float(row["recurrence_interval"][0]) == pytest.approx(10.0 * YEAR) == reported["sequence"].mean_interval
    assert float(row["slip_per_event"][0]) == pytest.approx(np.mean([4.5, 6.0, 5.5, 4.8])) == reported["mean_slip"]
    assert float(row["settled"][0]) == 0.0


def test_the_declared_slip_error_is_its_benchmarks_fit_and_holds_on_faults_it_left_out():
    """The slip bound is benchmarks/fault_3d_slip_error.py's fit, refitted here from the results files it reads
    (its order, its scale rounded up at most 1 %, a margin of 2, the recurrence's on BP5), so a rerun that moves the fit
    fails. On the drawn faults the fit left out (one changed kind at 100 m, one never settled), each coarser run's
    slip per event lies within its and the finest run's declared slip errors added, as each run declared them; and
    on every fault each run's slip does (a run saved before the slip error existed counts the square size's bound
    alone, which only tightens it)."""
    from faultslip.models.fault_3d.family import SLIP_DISCRETISATION, discretisation_error

    bench = load_benchmark("fault_3d_slip_error")
    resolution = json.loads((ROOT / "benchmarks" / "results" / "fault_3d_resolution.json").read_text(encoding="utf-8"))
    bp5 = json.loads((ROOT / "benchmarks" / "results" / "seas_bp5.json").read_text(encoding="utf-8"))
    pairs = bench.pairs(resolution, bp5)
    fitted = bench.fit(pairs)
    assert len(pairs) >= 13 and {pair["fault"] for pair in pairs} >= {"SEAS BP5-QD", "drawn 1", "drawn 4"}
    assert SLIP_DISCRETISATION["order"] == pytest.approx(fitted["order"])
    assert fitted["scale"] <= SLIP_DISCRETISATION["scale"] <= 1.01 * fitted["scale"]
    assert SLIP_DISCRETISATION["margin"] == bench.MARGIN == 2.0
    for pair in pairs:  # the fit covers every pair without its margin, and the declared bound with it, twice over
        declared = (discretisation_error(pair["resolution"], SLIP_DISCRETISATION)
                    + discretisation_error(pair["finest_resolution"], SLIP_DISCRETISATION))
        assert pair["difference"] <= declared / 2 + 1e-12, pair
    held_out = bench.check(resolution)
    assert {row["fault"] for row in held_out} == set(bench.HELD_OUT) and len(held_out) >= 3
    for row in held_out:
        assert row["allowed"] is not None and row["holds"], row
    for fault in resolution["judged"]:
        for row in fault["errors"]:
            assert row["holds_slip"] in (True, None), (fault["name"], row)
