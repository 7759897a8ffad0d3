"""Raw lab records in (rig units, machine stiffness, trend, steps and holds), Bayesian posteriors out.

Provenance: the records are the model's own (:func:`synthetic_raw_record`, known law); rsfmodel's truth
values are copied, with their source, beside faultslip's own computation of the same experiments.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.dynamics.rate_state.slider import LoadHistory, RateStateSlider, simulate_rate_state
from faultslip.errors import InputError, SolverError
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.resources import read_numeric_text
from faultslip.lab.posterior import Prior, parse_prior, sample_posterior
from faultslip.lab.rate_state_fit import fit_velocity_steps
from faultslip.lab.raw_records import (RawRecord, detect_steps, fit_each_step, read_rig_record, prepare_record, raw_record,
                                       read_raw_record, synthetic_raw_record)

UM = 1e-6
LAW = RateStateLaw(a=0.008, b=0.012, critical_slip=20 * UM, mu0=0.62, reference_speed=1 * UM)
AREA, NORMAL_LOAD, MACHINE = 0.0025, 25e3, 2e8  # 25 cm^2 at 10 MPa, 200 kN/mm: k = 8000 / m
EXAMPLE = "configs/example_raw_velocity_steps.txt"
ROOT = Path(__file__).resolve().parents[3]


def _small(seed=0, noise=1e-4, drift=0.0):
    """Two steps (1 -> 10 -> 1 um/s), 5 Hz: a record small enough to sample in a few seconds."""
    history = LoadHistory((0.0, 20.0, 40.0, 100.0), (1 * UM, 10 * UM, 1 * UM))
    return synthetic_raw_record(LAW, MACHINE, AREA, NORMAL_LOAD, history, rate=5.0, friction_noise=noise,
                                load_noise=0.0, displacement_noise=5e-9, drift=drift, seed=seed)


# --- reading -----------------------------------------------------------------------------------------------

def test_whitespace_text_with_units_inline_or_on_their_own_line(tmp_path):
    inline = tmp_path / "a.txt"
    inline.write_text("# rig 3\ntime(s) load_point_displacement[um]\n0 0\n1 1.5\n")
    columns = read_numeric_text(inline, "x")
    assert columns["time"][1] == "s" and columns["load_point_displacement"][1] == "um"
    separate = tmp_path / "b.dat"
    separate.write_text("time shear_load\n(ms) kN\n0 1\n2 3\n")
    columns = read_numeric_text(separate, "x")
    assert columns["time"][1] == "ms" and columns["shear_load"][0].tolist() == [1.0, 3.0]
    for text, words in (("time x\n0 1\n2\n", "1 fields, expected 2"),
                        ("time x\ns m km\n0 1\n", "units for 2 columns"), ("a a\n1 2\n", "twice"),
                        ("", "empty"), ("t v\n1 2\n3 nope\n", "not a number"),
                        ("t v\ns m\n", "no rows")):
        path = tmp_path / "bad.txt"
        path.write_text(text)
        with pytest.raises(InputError, match=words):
            read_numeric_text(path, "x")


def test_the_example_reads_the_same_from_text_csv_and_netcdf(tmp_path):
    import xarray as xr

    text = read_raw_record(EXAMPLE, area="25 cm^2")
    header = "time (s),load_point_displacement (um),shear_load (kN),normal_load (kN)"
    rows = np.loadtxt(EXAMPLE, comments="#", skiprows=3)
    csv = tmp_path / "r.csv"
    csv.write_text(header + "\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in rows) + "\n")
    from_csv = read_raw_record(csv, area="25 cm^2")
    netcdf = tmp_path / "r.nc"
    xr.Dataset({name: ("time", rows[:, i], {"units": unit}) for i, (name, unit) in
                enumerate((("load_point_displacement", "um"), ("shear_load", "kN"), ("normal_load", "kN")), start=1)},
               coords={"time": ("time", rows[:, 0], {"units": "s"})}).to_netcdf(netcdf)
    from_nc = read_raw_record(netcdf, area="25 cm^2")
    for other in (from_csv, from_nc):
        np.testing.assert_allclose(other.friction, text.friction, rtol=1e-9)
        np.testing.assert_allclose(other.load_point_displacement, text.load_point_displacement, atol=1e-12)


def test_a_notebook_table_is_a_raw_record():
    raw = raw_record({"time (s)": np.arange(60.0), "load_point_displacement (um)": np.arange(60.0),
                      "shear_load (kN)": np.full(60, 15.5), "normal_load (kN)": np.full(60, 25.0)}, area="25 cm^2")
    assert raw.friction[0] == pytest.approx(0.62) and raw.normal_stress[0] == pytest.approx(1e7)


def test_units_and_area_are_demanded_and_overridable(tmp_path):
    path = tmp_path / "r.txt"
    path.write_text("time load_point_displacement shear_stress normal_stress\n"
                    + "\n".join(f"{t} {t} {6.2} {10}" for t in range(60)) + "\n")
    with pytest.raises(InputError, match="has no unit"):
        read_raw_record(path)
    raw = read_raw_record(path, units={"time": "s", "load_point_displacement": "um", "shear_stress": "MPa",
                                       "normal_stress": "MPa"})
    assert raw.friction[0] == pytest.approx(0.62) and raw.load_point_displacement[-1] == pytest.approx(59e-6)
    with pytest.raises(InputError, match="not one of its columns"):
        read_raw_record(path, units={"temperature": "K"})
    loads = tmp_path / "l.txt"
    loads.write_text("time(s) load_point_displacement(um) shear_load(kN) normal_load(kN)\n"
                     + "\n".join(f"{t} {t} 1 2" for t in range(60)) + "\n")
    with pytest.raises(InputError, match="contact area"):
        read_raw_record(loads)


@settings(max_examples=60, deadline=None)
@given(st.binary(max_size=400), st.sampled_from((".txt", ".csv")))
def test_fuzzed_raw_files_fail_in_one_sentence(tmp_path_factory, payload, suffix):
    """Whatever bytes arrive, a raw record is read or refused with an InputError, never another exception."""
    path = tmp_path_factory.mktemp("fuzz") / f"r{suffix}"
    header = b"time(s) load_point_displacement(um) shear_load(kN) normal_load(kN)\n" if suffix == ".txt" else \
        b"time (s),load_point_displacement (um),shear_load (kN),normal_load (kN)\n"
    path.write_bytes(header + payload)
    try:
        record = read_rig_record(path, area="25 cm^2")
    except InputError as exc:
        assert "\n" not in str(exc).strip()
    else:
        assert isinstance(record, RawRecord)


# --- preparing ---------------------------------------------------------------------------------------------

def test_steps_holds_stiffness_and_trend_of_the_example():
    """The shipped record (configs/make_examples.py: steps at 100, 130, 230, 245 s, a hold from 300 to 360 s,
    drift -0.003 per mm) comes back to within a sample; the three forms of the same stiffness agree."""
    raw = read_raw_record(EXAMPLE, area="25 cm^2")
    prepared = prepare_record(raw, "200 kN/mm", area="25 cm^2", detrend="linear")
    history = prepared.record.history
    np.testing.assert_allclose(history.times, [0, 100, 130, 230, 245, 300, 360, 420], atol=0.1)
    np.testing.assert_allclose(history.speeds, [1e-6, 1e-5, 1e-6, 3e-5, 3e-6, 0.0, 3e-6], rtol=2e-3, atol=1e-9)
    assert prepared.stiffness == pytest.approx(8000.0, rel=1e-3)  # 2e8 N/m / (1e7 Pa x 0.0025 m^2), measured sigma_n
    for form in ("8e-3 1/um", "80 MPa/mm"):
        assert prepare_record(raw, form).stiffness == pytest.approx(prepared.stiffness, rel=1e-3)
    # the trend: -0.003 per mm of load-point travel, recovered within 15 %
    assert prepared.trend_coefficients[0] == pytest.approx(-0.003, rel=0.15)
    # the machine's stretch: sample slip = load point less (mu - mu_start) / k
    np.testing.assert_allclose(prepared.sample_displacement,
                               raw.load_point_displacement - (raw.friction - raw.friction[0]) / prepared.stiffness)


def test_given_step_times_replace_detection_and_bad_ones_are_refused():
    raw = _small()
    history = detect_steps(raw.time, raw.load_point_displacement, step_times=[20.0, 40.0])
    assert history.times == (0.0, 20.0, 40.0, raw.time[-1])
    np.testing.assert_allclose(history.speeds, [1e-6, 1e-5, 1e-6], rtol=1e-3)
    with pytest.raises(InputError, match="inside the record"):
        detect_steps(raw.time, raw.load_point_displacement, step_times=[500.0])
    with pytest.raises(InputError, match="detrend"):
        prepare_record(raw, "8e-3 1/um", detrend="cubic")
    with pytest.raises(InputError, match="stiffness"):
        prepare_record(raw, "3 kg")


def test_each_step_and_the_joint_fit_recover_the_law():
    """On the shipped example every step's own fit and the joint fit land within 2 % of the law it was made
    from (measured: within 1 %)."""
    prepared = prepare_record(read_raw_record(EXAMPLE, area="25 cm^2"), "200 kN/mm", area="25 cm^2",
                              detrend="linear")
    joint = fit_velocity_steps(prepared.record, prepared.stiffness)
    fits = [entry["fit"] for entry in fit_each_step(prepared)]
    assert len(fits) == 5  # four steps and the slide-hold-slide
    for fit in fits + [joint]:
        assert fit.parameters["a"] == pytest.approx(0.008, rel=0.02)
        assert fit.parameters["b"] == pytest.approx(0.012, rel=0.02)
        assert fit.parameters["critical_slip"] == pytest.approx(20e-6, rel=0.02)


# --- rsfmodel's truth values -------------------------------------------------------------------------------

#: rsfmodel (github.com/jrleeman/rsfmodel, commit d04d546), tests/rsf_tests.py: friction at t = 0..40 s of its
#: velocity-step examples (mu0 0.6, 1 -> 10 um/s at t = 10 s, V_ref 1 um/s), to 8 decimals. Copied for
#: comparison only; faultslip computes the same experiments itself below.
RSFMODEL = {
    ("aging", 0.005, 0.01, 10, None, None, 1e-3): [
        0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.60720485, 0.60186637, 0.5840091, 0.58563096,
        0.58899543, 0.58998186, 0.58879751, 0.58803412, 0.58825653, 0.58858313, 0.58860319, 0.58848625, 0.58844431,
        0.58847472, 0.58849913, 0.58849522, 0.58848506, 0.58848348, 0.58848674, 0.5884883, 0.58848756, 0.58848677,
        0.5884868, 0.58848711, 0.58848718, 0.5884871, 0.58848704, 0.58848706, 0.58848708, 0.58848708],
    ("slip", 0.01, 0.005, 10, None, None, 1e-3): [
        0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.60839299, 0.6146288, 0.61663335, 0.61451424,
        0.61239234, 0.61152559, 0.61133979, 0.61138186, 0.61145348, 0.61149781, 0.61151494, 0.61151781, 0.61151612,
        0.61151421, 0.61151317, 0.61151282, 0.61151279, 0.61151285, 0.6115129, 0.61151292, 0.61151293, 0.61151293,
        0.61151293, 0.61151293, 0.61151293, 0.61151293, 0.61151293, 0.61151293, 0.61151293, 0.61151293],
    ("aging", 0.012, 0.0185, 5, 0.0088, 50, 3e-3): [
        0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.61777816, 0.56719338, 0.57926411, 0.58134415,
        0.5741353, 0.57495495, 0.57393578, 0.57211002, 0.5714098, 0.57046462, 0.56953958, 0.56884951, 0.56819716,
        0.56762505, 0.56715188, 0.56674236, 0.5663961, 0.56610841, 0.56586767, 0.565668, 0.56550353, 0.56536809,
        0.56525698, 0.56516614, 0.56509194, 0.56503146, 0.56498223, 0.5649422, 0.56490967, 0.56488327],
    ("slip", 0.012, 0.0185, 5, 0.0088, 50, 8e-3): [
        0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.57317487, 0.57620828, 0.57423257, 0.57241419,
        0.57098114, 0.56981792, 0.56887496, 0.56810967, 0.56748807, 0.56698283, 0.56657196, 0.56623767, 0.56596561,
        0.56574412, 0.56556376, 0.56541686, 0.5652972, 0.56519972, 0.56512029, 0.56505557, 0.56500283, 0.56495985,
        0.56492482, 0.56489628, 0.56487301, 0.56485404, 0.56483859, 0.56482599, 0.56481572, 0.56480735],
}


def _rsfmodel_experiment(evolution, a, b, dc, b2, dc2, k, method="auto"):
    law = RateStateLaw(a=a, b=b, critical_slip=dc * UM, mu0=0.6, reference_speed=1 * UM, evolution=evolution,
                       b2=b2 or 0.0, critical_slip2=dc2 * UM if dc2 else None)
    run = simulate_rate_state(RateStateSlider(law, k / UM, 1.0), LoadHistory((0.0, 10.0, 40.0), (1 * UM, 10 * UM)),
                              t_eval=np.arange(0.0, 40.01, 1.0), rtol=1e-12, method=method)
    return run.friction


@pytest.mark.parametrize("case", list(RSFMODEL))
def test_rsfmodel_truth_values_are_reproduced(case):
    """faultslip's forward model (the fit's and the posterior's) against rsfmodel's stored truth: within
    1e-8 (measured 5e-9, the truth's own rounding); and against faultslip's LSODA path, to 1e-9."""
    ours = _rsfmodel_experiment(*case)
    np.testing.assert_allclose(ours, RSFMODEL[case], atol=1e-8)
    np.testing.assert_allclose(ours, _rsfmodel_experiment(*case, method="lsoda"), atol=1e-9)


def test_rsfmodel_experiments_agree_with_an_independent_integration():
    """The same experiments written out here in rsfmodel's own variables (friction and the states theta, in
    um and s) and integrated by scipy's Radau: faultslip's compiled path agrees to 1e-8, one-state and
    two-state, aging and slip."""
    from scipy.integrate import solve_ivp

    for evolution, a, b, dc, b2, dc2, k in RSFMODEL:
        def rates(t, y, a=a, b=b, dc=dc, b2=b2, dc2=dc2, k=k, evolution=evolution):
            mu, states = y[0], y[1:]
            pairs = [(b, dc)] + ([(b2, dc2)] if b2 else [])
            v = math.exp((mu - 0.6 - sum(bi * math.log(th / di) for (bi, di), th in zip(pairs, states))) / a)
            lp = 1.0 if t < 10 else 10.0
            if evolution == "aging":
                evolve = [1 - v * th / di for (_, di), th in zip(pairs, states)]
            else:
                evolve = [-(v * th / di) * math.log(v * th / di) for (_, di), th in zip(pairs, states)]
            return [k * (lp - v)] + evolve

        start = [0.6, dc] + ([dc2] if b2 else [])
        first = solve_ivp(rates, (0, 10), start, method="Radau", rtol=1e-11, atol=1e-13,
                          t_eval=np.arange(0.0, 10.01, 1.0))
        second = solve_ivp(rates, (10, 40), first.y[:, -1], method="Radau", rtol=1e-11, atol=1e-13,
                           t_eval=np.arange(10.0, 40.01, 1.0))
        reference = np.concatenate([first.y[0], second.y[0][1:]])
        np.testing.assert_allclose(_rsfmodel_experiment(evolution, a, b, dc, b2, dc2, k), reference, atol=1e-8)


# --- the posterior -----------------------------------------------------------------------------------------

def test_the_posterior_converges_covers_the_law_and_is_reproducible():
    prepared = prepare_record(_small(seed=3), "8e-3 1/um")
    posterior = sample_posterior(prepared.record, prepared.stiffness, samples=2000, seed=5)
    assert max(posterior.r_hat.values()) < 1.05 and min(posterior.effective_sample_size.values()) >= 400
    assert posterior.steps > 50 * max(posterior.autocorrelation_time.values())
    intervals = posterior.intervals()
    for name, truth in (("a", 0.008), ("b", 0.012), ("critical_slip", 20e-6)):
        low, high = intervals[name]
        assert low < truth < high
    assert float(np.median(posterior.noise)) == pytest.approx(1e-4 * 1.0, rel=0.2)  # shear noise / sigma_n
    again = sample_posterior(prepared.record, prepared.stiffness, samples=2000, seed=5)
    np.testing.assert_array_equal(again.samples, posterior.samples)
    entry = posterior.to_record()
    assert entry["samples_kind"] == "posterior" and len(entry["samples"]) <= 500
    band = posterior.predictive(prepared.record, draws=200)
    low, median, high = band["model"]
    assert np.all(low <= median) and np.all(median <= high)
    inside = np.mean((prepared.record.friction >= band["data"][0]) & (prepared.record.friction <= band["data"][1]))
    assert 0.9 < inside <= 1.0  # the predictive band holds ~95 % of the record


def test_an_unconverged_posterior_is_refused_with_its_diagnostics():
    prepared = prepare_record(_small(seed=3), "8e-3 1/um")
    with pytest.raises(SolverError, match="did not converge.*autocorrelation time.*R-hat.*effective samples"):
        sample_posterior(prepared.record, prepared.stiffness, samples=2000, max_steps=250, seed=1)


def test_priors_are_stated_changeable_and_checked():
    assert parse_prior("a=uniform:0:0.05") == ("a", Prior("uniform", 0.0, 0.05))
    assert Prior("loguniform", 1e-7, 1e-3).log_density(1e-5) == pytest.approx(-math.log(1e-5))
    assert Prior("normal", 0.01, 0.002).log_density(0.5) < -1000
    for text, words in (("c=uniform:0:1", "one of"), ("a=uniform:1:0", "low < high"), ("a=flat:0:1", "one of"),
                        ("b=normal:0", "name=kind"), ("critical_slip=loguniform:0:1", "positive")):
        with pytest.raises(InputError, match=words):
            parse_prior(text)
    prepared = prepare_record(_small(seed=3), "8e-3 1/um")
    with pytest.raises(SolverError, match="priors exclude"):
        sample_posterior(prepared.record, prepared.stiffness, priors={"a": Prior("uniform", 0.02, 0.05)},
                         samples=500)


def test_posterior_coverage_small_study():
    """The fast form of benchmarks/fit_coverage.py: 6 seeded records, 3 parameters each; the 95 % credible
    intervals must hold the truth in at least 16 of 18 (at 95 % the chance of fewer is 6 %; the seeds are fixed,
    and 18 of 18 were measured)."""
    hits = 0
    for seed in range(6):
        prepared = prepare_record(_small(seed=100 + seed, noise=3e-4), "8e-3 1/um")
        posterior = sample_posterior(prepared.record, prepared.stiffness, samples=1000, seed=seed)
        intervals = posterior.intervals()
        hits += sum(intervals[name][0] < truth < intervals[name][1]
                    for name, truth in (("a", 0.008), ("b", 0.012), ("critical_slip", 20e-6)))
    assert hits >= 16


# --- one command -------------------------------------------------------------------------------------------

def test_one_command_from_raw_record_to_fault_distribution(cli, tmp_path):
    raw = _small(seed=4)
    path = tmp_path / "rig.txt"
    path.write_text("time(s) load_point_displacement(mm) shear_load(kN) normal_load(kN)\n" + "\n".join(
        f"{t:.3f} {d * 1e3:.7f} {s * AREA / 1e3:.6f} {n * AREA / 1e3:.6f}"
        for t, d, s, n in zip(raw.time, raw.load_point_displacement, raw.shear_stress, raw.normal_stress)) + "\n")
    out = cli("fit", path, "--law", "rate-state", "--stiffness", "200 kN/mm", "--area", "25 cm^2", "--posterior",
              "--samples", "2000", "--each-step", "--plot", tmp_path / "fit.png", "--corner", tmp_path / "corner.png",
              "--name", "rig_gouge", "--json")
    assert out.code == 0, out.err
    assert out.json["a_posterior"]["r_hat"] < 1.05
    assert out.json["step_1"]["time"]["value"] == pytest.approx(20.0, abs=0.3)
    assert (tmp_path / "fit.png").stat().st_size > 10_000 and (tmp_path / "corner.png").stat().st_size > 10_000
    fault = cli("fault", "--lithology", "rig_gouge", "--zone-width", "10 km", "--normal-stress", "100 MPa",
                "--slip-rate", "30 mm/yr", "--shear-modulus", "30 GPa", "--json")
    assert fault.code == 0, fault.err
    quantiles = fault.json["stiffness_ratio_quantiles"]["value"]
    assert quantiles == sorted(quantiles) and quantiles[0] < quantiles[-1]
    assert any("posterior draws" in note for note in fault.json["notes"])
    # bad inputs: one sentence each
    assert_clean_error(cli("fit", path, "--law", "rate-state", "--stiffness", "200 kN/mm"), "contact area")
    assert_clean_error(cli("fit", path, "--law", "rate-state", "--stiffness", "8e-3 1/um", "--corner",
                           tmp_path / "c2.png"), "--posterior")
    assert_clean_error(cli("fit", path, "--law", "rate-state", "--stiffness", "8e-3 1/um", "--area", "25 cm^2",
                           "--posterior", "--prior", "a=uniform:1:0"), "low < high")
    assert json.loads(json.dumps(out.json))  # valid JSON throughout


# --- a rig that changes its sampling rate, and the real p655 (issue 46, item 2) -------------------------------

def test_steps_are_found_when_the_sampling_rate_changes_a_hundredfold():
    """p655 samples at 0.1 s, then 10 ms, then 1 ms through its fast steps. A record made at 1 kHz and thinned to
    0.1 s before 30 s: the detection works on bin means of a uniform grid, so its windows keep their duration,
    and finds the two steps and the three speeds."""
    law = RateStateLaw(a=0.008, b=0.012, critical_slip=20e-6, mu0=0.62, reference_speed=1e-6)
    history = LoadHistory((0.0, 40.0, 60.0, 80.0), (1e-6, 1e-5, 1e-4))
    raw = synthetic_raw_record(law, 2e8, 0.0025, 25e3, history, rate=1000.0, friction_noise=3e-4, load_noise=0.0,
                               displacement_noise=5e-8, seed=4)
    keep = (raw.time >= 30.0) | (np.arange(raw.time.size) % 100 == 0)
    time, displacement = raw.time[keep], raw.load_point_displacement[keep]
    found = detect_steps(time, displacement)
    assert len(found.times) == 4
    np.testing.assert_allclose(found.times[1:3], [40.0, 60.0], atol=0.2)
    np.testing.assert_allclose(found.speeds, [1e-6, 1e-5, 1e-4], rtol=0.02)
    assert isinstance(raw, RawRecord)


def test_p655_steps_hold_and_steady_state_dependence():
    """Penn State's p655 at 75 MPa (2400-3150 s): the steps and the hold that its load-point displacement shows
    (picked by eye from 2 s least-squares speeds: a hold from 2636.5 to 2683 s, then 2.3 -> 22.9 um/s near 3057 s,
    -> 228.6 um/s near 3081 s and back near 3093 s) are found through the change of sampling rate; the 2.3 -> 22.9
    um/s step is velocity strengthening, a - b = +0.0017 (the level change 0.0038 over ln 10); the 47 s hold heals
    0.0073 and relaxes 0.016 (regression values, computed here, pinned with their provenance). In windows of a
    fixed number of samples the 1 ms noise of the load point makes a segment run backwards."""
    from faultslip.lab.healing import healing, steady_state_dependence
    from faultslip.lab.look_reduction import run_r_file

    data = run_r_file(ROOT / "data" / "p655" / "p655_r").to_dataset()
    time = data["Time"].values
    inside = (time >= 2400) & (time <= 3150)
    origin = float(time[inside][0])
    raw = RawRecord(time[inside] - origin, data["LP_disp"].values[inside] * 1e-6 - data["LP_disp"].values[inside][0]
                    * 1e-6, data["Shear_stress"].values[inside] * 1e6, data["Nor_stress"].values[inside] * 1e6, "p655")
    with pytest.raises(InputError, match="backwards"):
        detect_steps(raw.time, raw.load_point_displacement, resample=False)
    prepared = prepare_record(raw, "0.5 MPa/um")
    history = prepared.record.history
    # the last two: 228.6 um/s falls to ~24 um/s (the mean of 0.25 s slopes from 3093.5 to 3095 s) near 3093.2 s,
    # then to 2.4 um/s near 3095.8 s; a coarse search's window (4 s) spans that short segment, the split finds it
    np.testing.assert_allclose(np.array(history.times[1:-1]) + origin,
                               [2636.5, 2683.0, 3057.5, 3081.5, 3093.2, 3095.8], atol=1.5)
    np.testing.assert_allclose(np.array(history.speeds) * 1e6, [2.29, 0.0, 2.29, 22.86, 228.6, 24.0, 2.4], rtol=0.03,
                               atol=1e-9)
    steps = steady_state_dependence(prepared.record)
    assert steps[0].a_minus_b == pytest.approx(0.00165, abs=2e-4)
    held = healing(prepared.record)
    assert held.hold_time[0] == pytest.approx(46.9, abs=1.0)
    assert held.healing[0] == pytest.approx(0.0073, abs=5e-4) and held.relaxation[0] == pytest.approx(0.016, abs=1e-3)


# --- spreadsheets (issue 46, item 1) ------------------------------------------------------------------------

def _workbook(path, header, rows):
    openpyxl = pytest.importorskip("openpyxl", reason="the xlsx extra (openpyxl) is not installed")
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.append(header)
    for row in rows:
        sheet.append(row)
    book.save(path)


def test_an_excel_workbook_reads_as_its_csv(tmp_path):
    raw = _small()
    header = ["time (s)", "load_point_displacement (um)", "shear_stress (MPa)", "normal_stress (MPa)"]
    rows = [[float(t), float(x * 1e6), float(tau / 1e6), float(sn / 1e6)] for t, x, tau, sn in
            zip(raw.time, raw.load_point_displacement, raw.shear_stress, raw.normal_stress)]
    _workbook(tmp_path / "run.xlsx", header, rows + [[None] * 4])
    (tmp_path / "run.csv").write_text(",".join(header) + "\n" + "".join(",".join(repr(v) for v in row) + "\n"
                                                                        for row in rows), encoding="utf-8")
    from_sheet, from_csv = read_rig_record(tmp_path / "run.xlsx"), read_rig_record(tmp_path / "run.csv")
    # openpyxl writes a number to 15 significant digits (Excel's own precision): equal to that, not bit for bit
    for name in ("time", "load_point_displacement", "shear_stress", "normal_stress"):
        np.testing.assert_allclose(getattr(from_sheet, name), getattr(from_csv, name), rtol=1e-14, atol=1e-20)


@pytest.mark.parametrize("header, rows, message", [
    (["time (s)", None, "friction"], [[1.0, 2.0, 0.6]], "column 2 of the header row has no name"),
    (["time (s)", "time (s)"], [[1.0, 2.0]], "two columns"),
    (["time (s)", "friction"], [[1.0, "sixty"]], "row 2: friction 'sixty' is not a number"),
    (["time (s)", "friction"], [], "at least one row of numbers"),
])
def test_a_malformed_workbook_is_one_sentence(tmp_path, cli, header, rows, message):
    _workbook(tmp_path / "bad.xlsx", header, rows)
    out = cli("fit", "--law", "rate-state", tmp_path / "bad.xlsx", "--stiffness", "1e-2 1/um")
    assert_clean_error(out, message)


@settings(max_examples=40, deadline=None)
@given(payload=st.binary(max_size=3000))
def test_fuzzed_workbooks_fail_in_one_sentence(tmp_path_factory, payload):
    from faultslip.io.resources import read_numeric_xlsx

    pytest.importorskip("openpyxl", reason="the xlsx extra (openpyxl) is not installed")
    path = tmp_path_factory.mktemp("xlsx") / "fuzz.xlsx"
    path.write_bytes(b"PK\x03\x04" + payload)
    with pytest.raises(InputError) as raised:
        read_numeric_xlsx(path, "fuzzed workbook")
    assert "\n" not in str(raised.value)


def test_a_records_metadata_travels_into_the_fits_report_and_its_bundle(tmp_path, cli):
    """A workbook's metadata sheet (experiment id, normal stress, area, stiffness) and a reduction's experiment name
    (xlook's header, p655intact100) reach the fit's report, its JSON and its bundle."""
    from faultslip.lab.look_reduction import run_r_file

    openpyxl = pytest.importorskip("openpyxl", reason="the xlsx extra (openpyxl) is not installed")
    raw = _small()
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.append(["time (s)", "load_point_displacement (um)", "shear_stress (MPa)", "normal_stress (MPa)"])
    for t, x, tau, sn in zip(raw.time, raw.load_point_displacement, raw.shear_stress, raw.normal_stress):
        sheet.append([float(t), float(x * 1e6), float(tau / 1e6), float(sn / 1e6)])
    meta = book.create_sheet("Metadata")
    for row in (["experiment", "gouge-17"], ["normal_stress", "10 MPa"], ["area", "25 cm^2"],
                ["machine_stiffness", "200 kN/mm"]):
        meta.append(row)
    book.save(tmp_path / "run.xlsx")
    out = cli("fit", "--law", "rate-state", tmp_path / "run.xlsx", "--stiffness", "8e-3 1/um", "--bootstrap", "0",
              "--bundle", tmp_path / "fit.zip", "--json")
    assert out.code == 0, out.err
    assert out.json["record_metadata"] == {"experiment": "gouge-17", "normal_stress": "10 MPa", "area": "25 cm^2",
                                           "machine_stiffness": "200 kN/mm"}
    import json
    import zipfile

    with zipfile.ZipFile(tmp_path / "fit.zip") as archive:
        assert json.loads(archive.read("report.json"))["record_metadata"]["experiment"] == "gouge-17"
    # the reduction's netCDF names its run, and a record read back from it carries the name
    assert run_r_file(ROOT / "data" / "p655" / "p655_r").to_dataset().attrs["experiment"] == "p655intact100"
    bad = openpyxl.Workbook()
    bad.active.append(["time (s)", "friction", "load_point_speed (um/s)"])
    bad.active.append([0.0, 0.6, 1.0])
    bad.create_sheet("metadata").append(["", "x"])
    bad.save(tmp_path / "bad.xlsx")
    assert_clean_error(cli("fit", "--law", "rate-state", tmp_path / "bad.xlsx", "--stiffness", "8e-3 1/um"),
                       "metadata sheet")


# --- short segments, fitted trends, correlated noise, a real run's columns (issue 46, item 2) -----------------

@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=8, max_value=60), st.integers(min_value=0, max_value=10_000))
def test_every_knots_two_line_fit_equals_least_squares(n, seed):
    """_hinge_fits' running sums give, at every knot, the residual of numpy's least squares on the same design."""
    from faultslip.lab.raw_records import _hinge_fits

    rng = np.random.default_rng(seed)
    time = np.sort(rng.uniform(0, 100, n)) + np.arange(n) * 1e-3
    displacement = np.cumsum(rng.uniform(0, 2, n)) + rng.normal(0, 0.3, n)
    knots, errors, coefficients = _hinge_fits(time, displacement)
    for k, error, coefficient in zip(knots, errors, coefficients):
        centred = time - time.mean()
        design = np.column_stack([np.ones(n), np.minimum(centred - centred[k], 0), np.maximum(centred - centred[k], 0)])
        solution, *_ = np.linalg.lstsq(design, displacement - displacement.mean(), rcond=None)
        exact = float(np.sum((design @ solution - (displacement - displacement.mean())) ** 2))
        assert error == pytest.approx(exact, rel=1e-7, abs=1e-9 * float(displacement @ displacement))
        np.testing.assert_allclose(coefficient[1:], solution[1:], rtol=1e-6, atol=1e-9)


def test_a_segment_shorter_than_the_search_window_is_found():
    """1 -> 100 -> 10 -> 1 um/s with the 10 um/s segment 3 s long in a 600 s record (the window is 15 s): the
    split finds it (p655's 24 um/s after 228.6 um/s), and each step lies within two samples of its true time."""
    history = LoadHistory((0.0, 300.0, 304.0, 307.0, 600.0), (1 * UM, 100 * UM, 10 * UM, 1 * UM))
    raw = synthetic_raw_record(LAW, MACHINE, AREA, NORMAL_LOAD, history, rate=20.0, friction_noise=1e-4,
                               load_noise=0.0, displacement_noise=5e-8, seed=3)
    found = detect_steps(raw.time, raw.load_point_displacement)
    np.testing.assert_allclose(found.times, history.times, atol=0.1)
    np.testing.assert_allclose(found.speeds, history.speeds, rtol=0.02)


def test_a_fitted_trend_recovers_the_drift_and_keeps_the_law():
    """A record drifting -4 friction per metre of load-point travel (p655's slip weakening at 228.6 um/s): the fit
    with the trend recovers the drift and a, b, D_c and leaves the noise; without it, D_c is off by many standard
    errors and the misfit triples."""
    from faultslip.lab.rate_state_fit import StepRecord

    raw = _small(seed=5, noise=1e-4, drift=-4.0)
    history = LoadHistory((0.0, 20.0, 40.0, 100.0), (1 * UM, 10 * UM, 1 * UM))  # _small's, not a detected one
    record = StepRecord(raw.time, raw.friction, history, "drifting")
    fitted = fit_velocity_steps(record, 8000.0, trend=True)
    # within 3.5 standard errors (a 1-in-2000 miss for a true interval; one seed's 95 % interval misses 1 in 20)
    for name, truth in (("a", LAW.a), ("b", LAW.b), ("critical_slip", LAW.critical_slip), ("trend", -4.0)):
        assert abs(fitted.parameters[name] - truth) < 3.5 * fitted.standard_errors[name], name
    assert fitted.residual_rms == pytest.approx(1e-4, rel=0.1)  # the noise, and nothing left over
    plain = fit_velocity_steps(record, 8000.0)
    assert plain.residual_rms > 2.5 * fitted.residual_rms
    assert abs(plain.parameters["critical_slip"] - LAW.critical_slip) > 10 * plain.standard_errors["critical_slip"]
    assert fitted.to_dict()["parameters"]["trend"]["units"] == "1/m"


def test_the_posterior_and_the_joint_fit_carry_a_fitted_trend():
    """The trend is sampled with the law (its 99.9 % credible interval holds the drift) and fitted per record jointly
    (within 3.5 standard errors)."""
    from faultslip.lab.rate_state_fit import StepRecord, fit_joint

    history = LoadHistory((0.0, 20.0, 40.0, 100.0), (1 * UM, 10 * UM, 1 * UM))  # _small's, not a detected one
    records = [StepRecord(raw.time, raw.friction, history, "drifting")
               for raw in (_small(seed=s, drift=-4.0) for s in (6, 7))]
    posterior = sample_posterior(records[0], 8000.0, trend=True, samples=2000, seed=1)
    low, high = posterior.intervals(0.999)["trend"]
    assert low <= -4.0 <= high
    band = posterior.predictive(records[0], draws=20)
    assert np.sqrt(np.mean((band["model"][1] - records[0].friction) ** 2)) < 3e-4  # the trend is in the band
    joint = fit_joint(records, 8000.0, trend=True)
    for i, row in enumerate(joint.per_record, start=1):
        assert abs(row["trend"] + 4.0) < 3.5 * joint.standard_errors[f"trend_{i}"]
    assert joint.to_dataset()["trend"].attrs["units"] == "1/m"
    with pytest.raises(InputError, match="trend fitted"):
        sample_posterior(records[0], 8000.0, priors={"trend": ("uniform", -10, 10)})


def test_law_selection_counts_correlated_points_once():
    """AR(1) noise (phi = 0.9) makes n (1 - rho) / (1 + rho) effective points, about n / 19; white noise leaves n
    to within rho's scatter, and only the correlated record's fits warn that their intervals are too narrow.
    lag_one_autocorrelation recovers phi of a long AR(1) series to 0.01."""
    from faultslip.lab.law_selection import lag_one_autocorrelation, select_law

    rng = np.random.default_rng(11)
    series = np.zeros(20_000)
    for i in range(1, series.size):
        series[i] = 0.9 * series[i - 1] + rng.standard_normal()
    assert lag_one_autocorrelation(series) == pytest.approx(0.9, abs=0.01)
    assert lag_one_autocorrelation(rng.standard_normal(100)) >= 0.0  # clipped
    record = prepare_record(_small(seed=8), "200 kN/mm", area="25 cm^2").record
    white = select_law(record, 8000.0, candidates=("aging", "slip"))
    assert white.effective_points == pytest.approx(white.points, rel=0.3)
    assert white.chosen == "aging"
    noise = np.zeros(record.time.size)
    for i in range(1, noise.size):
        noise[i] = 0.9 * noise[i - 1] + 1e-4 * rng.standard_normal()
    from faultslip.lab.rate_state_fit import StepRecord

    correlated = select_law(StepRecord(record.time, record.friction + noise, record.history, "ar1"), 8000.0,
                            candidates=("aging", "slip"))
    assert correlated.effective_points < 0.2 * correlated.points
    assert "effective points" in correlated.notes[0]
    # the fits say their intervals are too narrow on correlated noise, and not on independent noise
    assert any("residuals are correlated" in note for note in correlated.rows[0]["fit"].notes)
    assert not any("residuals are correlated" in note for note in white.rows[0]["fit"].notes)


P655_COLUMNS = {"time": "Time", "load_point_displacement": "LP_disp", "shear_stress": "Shear_stress",
                "normal_stress": "Nor_stress"}


@pytest.fixture(scope="module")
def p655_reduced(tmp_path_factory):
    from faultslip.lab.look_reduction import run_r_file

    path = tmp_path_factory.mktemp("p655") / "p655.nc"
    run_r_file(ROOT / "data" / "p655" / "p655_r").to_dataset().to_netcdf(path)
    return path


def test_p655_velocity_step_fitted_with_the_stiffness_free(p655_reduced):
    """p655 at 100 MPa, 2.29 -> 22.86 um/s at 3852.4 s (3830-3874 s), read by its reduction's own column names: the
    aging law with the machine's stiffness and a linear trend free. Regression values computed here, pinned with
    their provenance: a = 0.00575, b = 0.00390, D_c = 9.7 um, k = 1560 /m; a - b matches the steady levels'
    +0.0018 (test above, 75 MPa: +0.0017) and the rise after the step, k (V1 - V0) at its onset, is the same
    machine within 30 %."""
    from faultslip.lab.healing import steady_state_dependence

    record = read_rig_record(p655_reduced, columns=P655_COLUMNS, span=(3830.0, 3874.0))
    assert record.time[-1] == pytest.approx(44.0, abs=0.01)
    prepared = prepare_record(record, "2000 1/m")
    assert [round(v * 1e6, 1) for v in prepared.record.history.speeds] == [2.3, 22.9]
    fit = fit_velocity_steps(prepared.record, prepared.stiffness, stiffness_free=True, trend=True)
    p = fit.parameters
    assert p["a"] == pytest.approx(0.00575, rel=0.03) and p["b"] == pytest.approx(0.00390, rel=0.04)
    assert p["critical_slip"] == pytest.approx(9.7e-6, rel=0.06) and p["stiffness"] == pytest.approx(1560, rel=0.05)
    assert p["a"] - p["b"] == pytest.approx(steady_state_dependence(prepared.record)[0].a_minus_b, abs=5e-4)
    step = prepared.record.history.times[1]
    onset = (prepared.record.time > step) & (prepared.record.time < step + 0.15)
    slope = np.polyfit(prepared.record.time[onset], prepared.record.friction[onset], 1)[0]
    speeds = prepared.record.history.speeds
    assert slope / (speeds[1] - speeds[0]) == pytest.approx(p["stiffness"], rel=0.3)


def test_p655_columns_and_span_are_checked_in_one_sentence(p655_reduced, cli):
    with pytest.raises(InputError, match="no column 'LP'"):
        read_rig_record(p655_reduced, columns={**P655_COLUMNS, "load_point_displacement": "LP"})
    with pytest.raises(InputError, match="no row lies in the span"):
        read_rig_record(p655_reduced, columns=P655_COLUMNS, span=(1e6, 2e6))
    columns = ", ".join(f"{k}={v}" for k, v in P655_COLUMNS.items())
    for extra, message in ((["--span", "3900 s"], "--span takes"), (["--columns", "time"], "--columns takes"),
                           (["--span", "3900 s - 3800 s"], "earlier to a later"),
                           (["--detrend", "fitted", "--span", "10 m - 20 m"], "--span")):
        result = cli("fit", "--law", "rate-state", str(p655_reduced), "--stiffness", "2000 1/m", "--columns", columns,
                     *extra)
        assert_clean_error(result, message)


def test_every_lab_result_gives_xarray_with_cf_units(p655_reduced, tmp_path):
    """Issue 46, item 6: the records, the reader's file, the fits, the posterior, the steps' fits and the steady
    levels each give an xarray Dataset whose every variable has a unit udunits reads, and which netCDF holds."""
    from faultslip.lab.healing import healing, steady_state_dependence
    from faultslip.lab.look_files import read_look
    from faultslip.units import registry

    raw = _small(seed=9)
    prepared = prepare_record(raw, "200 kN/mm", area="25 cm^2")
    fit = fit_velocity_steps(prepared.record, prepared.stiffness, bootstrap=3, stiffness_free=True, trend=True)
    posterior = sample_posterior(prepared.record, prepared.stiffness, samples=500, seed=2, initial_fit=None)
    held = prepare_record(read_raw_record(EXAMPLE, area="25 cm^2"), "200 kN/mm", area="25 cm^2").record
    results = {"raw": raw, "prepared": prepared, "record": prepared.record, "fit": fit, "posterior": posterior,
               "each_step": fit_each_step(prepared), "steady": steady_state_dependence(prepared.record),
               "healing": healing(held), "look": read_look(ROOT / "data" / "p655" / "p655intact100l"),
               "span": read_rig_record(p655_reduced, columns=P655_COLUMNS, span=("64 min", "65 min"))}
    for name, result in results.items():
        dataset = result.to_dataset()
        assert dataset.data_vars, name
        for variable in dataset.data_vars.values():
            if variable.dtype.kind in "fi":
                registry().Unit(variable.attrs["units"])  # udunits-style, read by pint
        dataset.to_netcdf(tmp_path / f"{name}.nc")
    assert results["span"].time[-1] == pytest.approx(60.0, abs=0.15)  # 3840 s to 3900 s, sampled at 0.1 s
    assert results["fit"].to_dataset()["stiffness_bootstrap"].sizes["draw"] == 3
    assert results["posterior"].to_dataset()["critical_slip"].attrs["units"] == "m"
    steps = results["each_step"].to_dataset()
    np.testing.assert_allclose(steps["a"], [entry["fit"].parameters["a"] for entry in results["each_step"]])
    np.testing.assert_allclose(results["steady"].to_dataset()["a_minus_b"],
                               [row.a_minus_b for row in results["steady"]])


def test_the_shipped_raw_records_documented_command_covers_its_headers_truth(cli):
    """configs/README.md's command for the raw record, run as written: its 95 % intervals hold the a, b and D_c its
    header states (the record drifts with slip; --detrend linear, once documented, gave intervals that excluded
    them)."""
    import re
    import shlex

    root = Path(__file__).resolve().parents[3]
    line = next(text for text in (root / "configs" / "README.md").read_text().splitlines()
                if "example_raw_velocity_steps.txt" in text and text.startswith("faultslip fit"))
    header = (root / "configs" / "example_raw_velocity_steps.txt").read_text().splitlines()[1]
    truth = {"a": float(re.search(r"\ba ([0-9.]+)", header).group(1)),
             "b": float(re.search(r"\bb ([0-9.]+)", header).group(1)),
             "critical_slip": float(re.search(r"D_c ([0-9.]+) um", header).group(1)) * 1e-6}
    arguments = [word.replace("configs/", str(root / "configs") + "/") for word in shlex.split(line)[1:]]
    result = cli(*arguments, "--json")
    assert result.code == 0, result.err
    for name, value in truth.items():
        entry = result.json[f"{name}_95"]
        low, high = entry["value"] if isinstance(entry, dict) else entry  # D_c's carries its units (m)
        assert low <= value <= high, (name, low, value, high)


def test_the_posterior_and_the_bootstrap_show_progress_with_their_expected_time_first(monkeypatch):
    """A long fit is never silent: the posterior reports its steps against a total revised as the chain's
    autocorrelation time is measured, and the bootstrap its refits; each says first what it expects to cost."""
    import io

    from faultslip.io import progress as progress_module
    from faultslip.io.progress import Progress
    from faultslip.lab.rate_state_fit import fit_velocity_steps

    prepared = prepare_record(_small(seed=3), "8e-3 1/um")
    seen = []
    posterior = sample_posterior(prepared.record, prepared.stiffness, samples=2000, seed=5,
                                 progress=lambda done, total: seen.append((done, total)))
    assert seen and all(done <= total for done, total in seen)
    assert [done for done, _ in seen] == sorted(done for done, _ in seen)
    assert seen[-1][0] == posterior.steps  # the last report is the chain's length
    refits = []
    fit_velocity_steps(prepared.record, prepared.stiffness, bootstrap=6, progress=lambda d, t: refits.append((d, t)))
    integrations = [(d, t) for d, t in refits if t != 6]  # the fit itself: integrations against trf's bound
    assert integrations and integrations[-1][0] == integrations[-1][1]
    refits = [(d, t) for d, t in refits if t == 6]
    assert refits[0] == (0, 6) and refits[-1] == (6, 6)
    monkeypatch.setattr(progress_module, "ANNOUNCE_FROM", 0.0)  # announce even this short a run
    stream = io.StringIO()
    sample_posterior(prepared.record, prepared.stiffness, samples=2000, seed=5, progress=Progress("posterior",
                                                                                                 stream=stream))
    first = stream.getvalue().splitlines()[0]
    assert first.startswith("faultslip: sampling the posterior: about ") and "walkers" in first


def test_each_steps_fits_and_law_selection_show_progress(monkeypatch):
    """Fits of each step's window and of each candidate law report (done, total) and, after the first, say what
    the rest will cost (announced from 10 s: here from 0, to see it)."""
    import io

    from faultslip.io import progress as progress_module
    from faultslip.io.progress import Progress
    from faultslip.lab.law_selection import select_law

    prepared = prepare_record(_small(seed=3), "8e-3 1/um")
    seen = []
    fits = fit_each_step(prepared, progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (len(fits), len(fits)) and [d for d, _ in seen] == sorted(d for d, _ in seen)
    monkeypatch.setattr(progress_module, "ANNOUNCE_FROM", 0.0)
    stream = io.StringIO()
    select_law(prepared.record, prepared.stiffness, candidates=("aging", "slip"), progress=Progress("laws", stream=stream))
    assert "fitting each candidate law: 2 in all, about" in stream.getvalue()
