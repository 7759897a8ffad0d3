"""Rate-and-state friction in studies: K / K_c in closed form in every cell, cycles where asked."""

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.dynamics.rate_state import native
from faultslip.dynamics.rate_state.slider import RateStateSlider, fault_cycles
from faultslip.errors import InputError
from faultslip.fault.rate_state_cells import METHOD_CODES, REGIME_CODES, rate_state_cells
from faultslip.friction.rate_state import RateStateLaw
from faultslip.studies.grid import parse_study, sweep

BASE = "san_andreas_1906_rate_state.toml"
YEAR = 365.25 * 86400.0


@settings(max_examples=60, deadline=None)
@given(modulus=st.floats(1e9, 1e11), width=st.floats(10.0, 1e5), sigma=st.floats(1e5, 2e8),
       a=st.floats(1e-3, 0.03), b=st.floats(0.0, 0.03), critical_slip=st.floats(1e-6, 1.0))
def test_every_cell_gets_ruinas_critical_stiffness_in_closed_form(modulus, width, sigma, a, b, critical_slip):
    """K / K_c = (G / D) D_c / (sigma_n (b - a)); stable (flag 1) at and above 1, velocity strengthening where
    b <= a, with an infinite ratio: K_c <= 0 means every stiffness slides stably (Ruina 1983)."""
    out = rate_state_cells(shear_modulus=modulus, zone_width=width, normal_stress=sigma, plate_rate=1e-9, a=a, b=b,
                           critical_slip=critical_slip)
    ratio = float(out["stiffness_ratio"])
    assert out["method"] == METHOD_CODES["closed_form"]
    if b <= a:
        assert ratio == np.inf and out["regime"] == REGIME_CODES["velocity_strengthening"]
    else:
        assert ratio == pytest.approx(modulus / width * critical_slip / (sigma * (b - a)), rel=1e-12)
        assert out["regime"] == (REGIME_CODES["stick_slip"] if ratio < 1 else REGIME_CODES["stable_sliding"])
    # mu_ss = mu0 + (a - b) ln(V / V0) at the plate rate (V0 1 um/s, mu0 0.6)
    assert float(out["steady_state_friction"]) == pytest.approx(0.6 + (a - b) * np.log(1e-9 / 1e-6), rel=1e-12)


def test_a_cells_cycles_are_the_faults_own():
    """A study cell's cycles are fault_cycles on the same fault, to the last digit, and a sweep of a
    parameter the cycles do not depend on (rupture length) reuses them: M0 scales with L exactly."""
    law = RateStateLaw(a=0.010, b=0.015, critical_slip=0.008)
    slider = RateStateSlider.at_fault(law, 3.2e10, 20e3, 50e6, density=2670.0, shear_wave_speed=3464.0)
    # tolerance 1e-6: dopri5's declared error 20 rtol asks rtol 3e-8 (auto, K / K_c 0.05)
    direct = fault_cycles(slider, 1e-9, cycles=3, spin_up=2, rtol=3e-8)
    out = rate_state_cells(shear_modulus=3.2e10, zone_width=20e3, normal_stress=50e6, plate_rate=1e-9, a=0.010,
                           b=0.015, critical_slip=0.008, density=2670.0, shear_wave_speed=3464.0,
                           rupture_length=np.array([50e3, 100e3, 200e3]), seismogenic_depth=15e3, cycles=3)
    assert np.all(out["recurrence_period"] == direct.recurrence)
    assert np.all(out["slip_per_event"] == np.mean(direct.slip_per_event))
    assert direct.method == ("dopri5_compiled" if native.available() else "dopri5")  # the same integrator as auto's
    assert np.all(out["method"] == METHOD_CODES[direct.method]) and np.all(out["regime"] == REGIME_CODES["stick_slip"])
    assert out["seismic_moment"][1] / out["seismic_moment"][0] == pytest.approx(2.0, rel=1e-15)
    balance = abs(np.mean(direct.cycle_slip) / (1e-9 * direct.recurrence) - 1)
    # declared: the integrator's 20 rtol, what settling left, or the plate balance, whichever is largest
    declared = max(balance, 20 * 3e-8, direct.estimated_relative_error)
    assert out["numerical_error"][0] == pytest.approx(declared) and balance < 1e-5


def test_stable_cells_slide_at_the_plate_rate_and_never_fake_events():
    out = rate_state_cells(shear_modulus=3.2e10, zone_width=np.array([20e3, 10.0]), normal_stress=50e6,
                           plate_rate=1e-9, a=np.array([[0.010], [0.02]]), b=0.015, critical_slip=0.008, cycles=2)
    # rows: a 0.010 (unstable at 20 km, stable at 10 m), a 0.02 (velocity strengthening)
    assert out["regime"].tolist() == [[0, 1], [2, 2]]
    stable = out["regime"] > 0
    assert np.all(out["slip_per_event"][stable] == 0) and np.all(np.isnan(out["recurrence_period"][stable]))
    assert np.all(out["peak_slip_rate"][stable] == 1e-9) and np.all(out["method"][stable] == 0)


def test_a_solver_failure_is_flagged_not_hidden(monkeypatch):
    from faultslip.errors import SolverError
    from faultslip.fault import rate_state_cells as cells

    def failing(*args, **kwargs):
        raise SolverError("dopri5 failed")

    monkeypatch.setattr(cells, "fault_cycles", failing)
    out = cells.rate_state_cells(shear_modulus=3.2e10, zone_width=20e3, normal_stress=50e6, plate_rate=1e-9,
                                 a=0.010, b=0.015, critical_slip=0.008, cycles=2)
    assert out["method"] == METHOD_CODES["solver_failed"] and np.isnan(out["slip_per_event"])


def test_sweep_in_memory_and_lazy_agree_and_carry_cf_flags():
    dims = dict(critical_slip=["10 um", "8 mm", "20 cm"], evolution=["aging", "slip"])
    eager = sweep(BASE, cycles=2, **dims)
    lazy = sweep(BASE, cycles=2, chunks={"critical_slip": 1}, **dims)
    assert lazy["slip_per_event"].chunks is not None
    lazy = lazy.compute()
    for name in eager.data_vars:
        np.testing.assert_array_equal(eager[name].values, lazy[name].values)
    assert eager["critical_slip"].attrs["units"] == "m"
    assert eager["method"].attrs["flag_meanings"] == "solver_failed closed_form lsoda dopri5 dopri5_compiled"
    # auto: LSODA at a lab D_c (K / K_c 6e-5), dopri5 at BP1's 8 mm; 20 cm is past K_c (stable)
    assert eager["method"].values[:, 0].tolist() == [1, 3 if native.available() else 2, 0]
    assert eager["regime"].values[2].tolist() == [1, 1]
    # the slip law's events are smaller than the aging law's on this fault (measured 0.83 at 8 mm)
    ratio = eager["slip_per_event"].values[1, 1] / eager["slip_per_event"].values[1, 0]
    assert 0.7 < ratio < 0.95


def test_cli_sweep_writes_counts_and_reproduces(cli, tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(f'[study]\nbase = "{BASE}"\ncycles = 2\n[sweep]\n'
                     'critical_slip = ["1 mm", "8 mm", "30 cm"]\na = [0.010, 0.02]\n', encoding="utf-8")
    out = tmp_path / "rs.nc"
    result = cli("sweep", study, "-o", out, "--json")
    assert result.code == 0, result.err
    counts = result.json["cells_by_flag"]
    assert counts["regime"] == {**counts["regime"], "stick_slip": 2, "stable_sliding": 1, "velocity_strengthening": 3}
    assert counts["method"]["solver_failed"] == 0 and counts["method"]["closed_form"] == 4  # two cells simulated
    # the two blocks stand for faults: D_c 8 mm at D / h* 4.3 (model error 1.53), 1 mm at 34, past the
    # calibration (unbounded: JSON null, counted); their own cycles' error stays small
    assert counts["largest_estimated_relative_error"] is None and counts["unbounded_error_cells"] == 1
    assert counts["largest_bounded_estimated_relative_error"] == pytest.approx(1.5302, abs=1e-4)
    with xr.open_dataset(out) as written:
        assert float(written["numerical_error"].max()) < 1e-4
    with xr.open_dataset(out) as written:
        assert written["stiffness_ratio"].dims == ("critical_slip", "a")
        assert "faultslip_study" in written.attrs
    again = cli("reproduce", out, "--json")  # an unnamed study: the title names the original file, not this one
    assert again.code == 0, again.err
    assert again.json["matches"] and again.json["largest_difference"] == 0.0


@pytest.mark.parametrize("study, message", [
    ('[study]\nbase = "san_andreas_1906.toml"\ncycles = 3\n[sweep]\nslip_rate = ["1 mm/yr"]\n',
     "cycles applies to rate-and-state studies"),
    (f'[study]\nbase = "{BASE}"\nmethod = "closed_form"\n[sweep]\na = [0.01]\n', "method of a rate-and-state study"),
    (f'[study]\nbase = "{BASE}"\ncycles = -1\n[sweep]\na = [0.01]\n', "cycles must be a whole number"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\na = [0.01, 1.5]\n', "rate-and-state a must be in (0, 1)"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\ncritical_slip = ["1 km"]\n', "D_c must lie between 1e-09 and 10 m"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\nevolution = ["ageing"]\n', "evolution law must be one of"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\nfit = ["granodiorite"]\n', "not a rate-and-state fit"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\nmu_so = [0.6]\n', "unknown parameter 'mu_so'"),
    (f'[study]\nbase = "{BASE}"\n[sweep]\nnormal_stress = ["1 MPa"]\nshear_stress = ["1 MPa"]\n', "sweep one"),
])
def test_bad_rate_state_studies_are_one_sentence(cli, tmp_path, study, message):
    path = tmp_path / "bad.toml"
    path.write_text(study, encoding="utf-8")
    assert_clean_error(cli("sweep", path, "-o", tmp_path / "out.nc"), message)
    assert not (tmp_path / "out.nc").exists()


def test_the_budget_counts_only_the_unstable_cells_cycles(cli, tmp_path, monkeypatch):
    """A million cells of K / K_c alone run in a second; the same grid with cycles is refused up front,
    and one whose cells are all stable (D_c past K_c) is not: only unstable cells are simulated."""
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "600")
    grid = 'critical_slip = { logspace = ["1 um", "1 mm", 1000] }\nslip_rate = { logspace = ["1 mm/yr", "5 cm/yr", 1000] }\n'
    study = tmp_path / "big.toml"
    study.write_text(f'[study]\nbase = "{BASE}"\ncycles = 5\n[sweep]\n{grid}', encoding="utf-8")
    assert_clean_error(cli("sweep", study, "-o", tmp_path / "big.nc"), "allow-large")
    parsed = parse_study(study.read_text(encoding="utf-8"), "big.toml")
    # every cell unstable and stiff: at most LSODA's cost at the rtol its declared error needs for 1e-6, its 5
    # cycles measured after those it takes to settle (a / b = 2 / 3) by its calibrated cost model
    # (faultslip.dynamics.rate_state.methods), and a cell's fixed cost; auto takes the C stepper where it is built
    # and cheaper (its steps grow as 9.3 / (K / K_c))
    from faultslip.dynamics.rate_state.methods import CYCLE_METHODS, SECONDS_PER_STEP, cycle_steps, steps_per_cycle
    from faultslip.fault.rate_state_cells import CELL_OVERHEAD

    lsoda = CYCLE_METHODS["lsoda"].assess(1e-3, 1e-6, 5, a_over_b=0.010 / 0.015)
    per_cell = lsoda.estimated_cost + CELL_OVERHEAD
    # the cycles' steps include settling: more than 8.5 cycles' worth at this K / K_c and a / b
    steps = cycle_steps("lsoda", lsoda.settings["rtol"], 1e-3, 0.010 / 0.015, 5)
    assert lsoda.estimated_cost == pytest.approx(steps * SECONDS_PER_STEP["lsoda"], rel=1e-12)
    assert steps > 8.5 * steps_per_cycle("lsoda", lsoda.settings["rtol"], 1e-3)
    assert 0.01 < parsed.seconds_per_cell() <= per_cell * 1.01 and 0.05 < per_cell < 0.3
    if not native.available():
        assert parsed.seconds_per_cell() == pytest.approx(per_cell, rel=0.01)
    stable = parse_study(study.read_text(encoding="utf-8").replace('["1 um", "1 mm", 1000]', '["1 m", "2 m", 1000]'),
                         "big.toml")
    assert stable.seconds_per_cell() < 1e-5


def test_a_saved_fit_is_a_category(cli):
    """fit = [NAME] takes a, b, D_c, mu0, V0 and the evolution law from each saved fit (and G if saved)."""
    result = cli("fit", "--law", "rate-state", "configs/example_velocity_steps.csv", "--stiffness", "1e-2 1/um",
                 "--bootstrap", "2", "--name", "study_gouge", "--shear-modulus", "30 GPa")
    assert result.code == 0, result.err
    from faultslip.friction.materials import user_rate_state_fits

    law, _ = user_rate_state_fits()["study_gouge"]
    out = sweep(BASE, fit=["study_gouge"], zone_width=["1 km", "20 km"])
    expected = 30e9 / np.array([1e3, 20e3]) * law.critical_slip / ((250e5 / law.mu0) * (law.b - law.a))
    np.testing.assert_allclose(out["stiffness_ratio"].values[0], expected, rtol=1e-12)
    with pytest.raises(InputError, match="not a rate-and-state fit"):
        sweep(BASE, fit=["granodiorite"])


def test_the_bundled_rate_state_study_runs_and_spreads_over_blocks():
    """configs/study_rate_state.toml: 26 cells, 24 unstable; blocks of about BLOCK_SECONDS of work each, so a study
    estimated at several blocks' work is spread over several, not one."""
    from faultslip.studies import streaming
    from faultslip.studies.grid import compute_block, load_study
    from faultslip.studies.streaming import default_chunk_cells, plan_blocks

    study = load_study("configs/study_rate_state.toml")
    assert study.cycles == 5 and study.size == 26
    with pytest.MonkeyPatch.context() as patch:  # the Python integrators, and blocks of a quarter of their work
        patch.setattr(native, "_cycles", None)
        work = study.size * study.seconds_per_cell()
        patch.setattr(streaming, "BLOCK_SECONDS", work / 4)
        _, blocks = plan_blocks(study, default_chunk_cells(study))
    assert work > 0.1 and len(blocks) >= 4
    corner = compute_block(study, {"critical_slip": slice(0, 13, 12), "evolution": slice(0, 1)})
    # a lab D_c (10 um) takes LSODA and has cycles; 20 cm is past K_c
    assert corner["method"].values.ravel().tolist() == [1, 0]
    assert corner["regime"].values.ravel().tolist() == [0, 1]


def test_a_study_cell_declares_the_model_error_its_run_declares():
    """A cell's cycles are one block's; as the fault's answer they carry the model error `run` declares for the
    same fault (the zone-width calibration at D / h*), and the declared error is the larger of it and the cycles'
    own. Before, a study of the 1906 fault wrote 1e-6 where its run declared 1.53. A stable cell (D / h* below the
    calibration) has an unbounded model error but an exact closed form; b <= a has neither model's earthquakes."""
    import faultslip

    run = faultslip.run(BASE)
    out = sweep(BASE, cycles=2, critical_slip=["8 mm", "1 m"], a=[0.010, 0.02])
    stick, stable, creeping = (out.isel(critical_slip=0, a=0), out.isel(critical_slip=1, a=0),
                               out.isel(critical_slip=0, a=1))
    assert float(stick["model_error"]) == pytest.approx(float(run["model_error"]), rel=1e-12)
    assert float(stick["width_over_nucleation"]) == pytest.approx(float(run["width_over_nucleation"]), rel=1e-12)
    assert float(stick["estimated_relative_error"]) == max(float(stick["numerical_error"]), float(stick["model_error"]))
    assert float(stick["numerical_error"]) < 1e-5
    assert stable["regime"] == REGIME_CODES["stable_sliding"] and float(stable["model_error"]) == np.inf
    assert float(stable["estimated_relative_error"]) == 0.0
    assert np.isnan(float(creeping["model_error"])) and float(creeping["width_over_nucleation"]) == 0.0


def test_a_run_to_a_file_integrates_each_distinct_cell_once(tmp_path, monkeypatch):
    """The cells declare their outputs (names, types, CF flags with solver_failed's -1), so a sweep to a file
    learns its layout without integrating a cell first (it integrated the first cell twice); the declared layout
    is the computed one, with a moment and without."""
    from faultslip.fault import rate_state_cells as cells_module
    from faultslip.studies.grid import StudyLayout, template_block
    from faultslip.studies.streaming import run_study

    integrated = []
    original = cells_module._one_cell
    monkeypatch.setattr(cells_module, "_one_cell", lambda row, *a: integrated.append(tuple(row)) or original(row, *a))
    from faultslip.io.resources import bundled_dir

    without_rupture = tmp_path / "no_rupture.toml"  # no rupture length: no moment among the outputs
    without_rupture.write_text((bundled_dir("configs") / BASE).read_text(encoding="utf-8").replace('rupture_length = "270 mi"\n', ""),
                               encoding="utf-8")
    for base, moment in ((BASE, True), (without_rupture.as_posix(), False)):
        study = parse_study(f'[study]\nbase = "{base}"\ncycles = 2\n[sweep]\ncritical_slip = ["4 mm", "8 mm", "1 m"]\n',
                            "s.toml", base_dir=tmp_path)
        declared = template_block(study)
        computed = sweep(base, cycles=2, critical_slip=["4 mm"])
        assert list(declared.data_vars) == list(computed.data_vars)
        for name, layout in declared.data_vars.items():
            assert layout.dtype == computed[name].dtype, name
            assert {k: str(v) for k, v in layout.attrs.items()} == {k: str(v) for k, v in computed[name].attrs.items()}
        assert ("seismic_moment" in declared.data_vars) == moment and isinstance(declared, StudyLayout)
        integrated.clear()
        run_study(study, tmp_path / f"out{moment}.nc")
        assert len(integrated) == len(set(integrated)) == 2  # two unstable cells, each once
