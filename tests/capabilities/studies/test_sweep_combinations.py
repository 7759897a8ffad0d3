"""Every sweepable parameter, alone and in any combination, gives the cells of the scalar computation.

An audit found 45 of 148 single and paired sweeps crashing (issue 9): the cell kernel wrote
results in place into a buffer smaller than the grid. The property below draws random subsets
of parameters and random shapes and compares every cell with ``Fault.estimate`` (fault studies)
or ``solve`` on ``SliderSystem.from_preset`` (lab studies), which share no grid code.
"""

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from faultslip.errors import InputError
from faultslip.fault.scaling import Fault
from faultslip.dynamics.methods import solve
from faultslip.fault.scene import read_slider_scene
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.fault.spring_slider_cells import FAULT_PARAMETERS, LAB_PARAMETERS
from faultslip.studies.grid import sweep

FAULT_VALUES = {
    "lithology": ["granodiorite", "pyrite", "black_marble"],
    "shear_modulus": ["0.2e6 bar", "0.3e6 bar", "30 GPa"],
    "zone_width": ["10 km", "20 km", "13 mi"],
    "normal_stress": ["300 bar", "400 bar", "50 MPa"],
    "shear_stress": ["200 bar", "250 bar", "30 MPa"],
    "slip_rate": ["10 mm/yr", "30 mm/yr", "2 in/yr"],
    "mu_so": [0.7, 0.8, 0.9],
    "mu_m": [0.3, 0.4, 0.45],
    "b": [0.0, 10.0, 1e3],
    "d": [0.5, 1.0, 1.3],
    "rupture_length": ["100 km", "200 km", "270 mi"],
    "seismogenic_depth": ["10 km", "15 km", "12 km"],
    "damping_ratio": [0.0, 0.1, -0.05],
    "density": ["2600 kg/m^3", "2800 kg/m^3", "3000 kg/m^3"],
    "shear_wave_speed": ["3 km/s", "3.5 km/s", "2.8 km/s"],
}
LAB_VALUES = {
    "preset": ["glass_dry", "steel_dry", "pyrite_water"],
    "platform_speed": ["1e-4 in/s", "1e-3 in/s", "1e-5 in/s"],
    "loading_rate": ["0.01 1/s", "0.1 1/s", "1 1/s"],
    "damping_ratio": [0.0, 0.05, 0.2],
    "kinetic_slope": ["0 s/m", "0.5 s/m", "2 s/m"],
    "normal_load": ["100 lbf", "200 lbf", "1 kN"],
    "stiffness": ["1e4 lbf/in", "2e4 lbf/in", "5e6 N/m"],
}
EXCLUSIVE = [{"normal_stress", "shear_stress"}, {"platform_speed", "loading_rate"}]
_FAULT_BASE = read_slider_scene("san_andreas_1906.toml")
_LAB_BASE = read_slider_scene("lab_glass_dry.toml")


def _allowed(names):
    return not any(pair <= set(names) for pair in EXCLUSIVE)


def _fault_cell(chosen):
    inputs = dict(_FAULT_BASE.fault_inputs)
    if "lithology" in chosen:  # a swept lithology supplies G and the friction law unless swept too
        for key in ("shear_modulus", "mu_so", "mu_m", "b", "d"):
            inputs.pop(key, None)
    if "normal_stress" in chosen:
        inputs.pop("shear_stress", None)
    if "shear_stress" in chosen:
        inputs.pop("normal_stress", None)
    inputs.update(chosen)
    return Fault(**inputs).estimate()


def _lab_cell(chosen):
    lab = dict(_LAB_BASE.tables["lab"])
    lab.update(chosen)
    if "loading_rate" in chosen:
        lab.pop("platform_speed", None)
    preset = lab.pop("preset")
    return solve(SliderSystem.from_preset(preset, **lab), tolerance=1e-6).cycle


def _compare(base, values, scalar):
    try:
        dataset = sweep(base, **values)
    except InputError as exc:  # a refusal must be what the scalar computation also refuses
        cells = list(itertools.product(*values.values()))
        refused = 0
        for cell in cells:
            try:
                scalar(dict(zip(values, cell)))
            except InputError:
                refused += 1
        assert refused, f"the sweep refused ({exc}) but every scalar cell computes"
        return
    names = list(values)
    for cell in itertools.product(*(range(len(v)) for v in values.values())):
        chosen = {name: values[name][i] for name, i in zip(names, cell)}
        row = dataset.isel({name: i for name, i in zip(names, cell)})
        if "outside_domain" in dataset and int(row["outside_domain"]) == 1:  # flagged: what the scalar refuses
            with pytest.raises(InputError):
                scalar(chosen)
            assert int(row["regime"]) == -1 and np.isnan(float(row["slip_per_event"]))
            continue
        expected = scalar(chosen)
        codes = {"stick_slip": 0, "steady_sliding": 1, "growing_oscillation": 2}
        assert int(row["regime"]) == codes[expected.regime], str(chosen)
        if expected.regime == "steady_sliding":  # the study's convention: no slip, no recurrence
            assert float(row["slip_per_event"]) == 0.0 and np.isnan(float(row["recurrence_period"]))
            continue
        period = getattr(expected, "recurrence_period", None) or expected.period
        amplitude = getattr(expected, "slip_per_event", None) or expected.amplitude
        np.testing.assert_allclose(float(row["recurrence_period"]), period, rtol=1e-5, err_msg=str(chosen))
        np.testing.assert_allclose(float(row["slip_per_event"]), amplitude, rtol=1e-5, err_msg=str(chosen))


@pytest.mark.parametrize("name", list(FAULT_PARAMETERS))
def test_every_fault_parameter_sweeps_alone(name):
    _compare("san_andreas_1906.toml", {name: FAULT_VALUES[name][:2]}, _fault_cell)


@pytest.mark.parametrize("name", list(LAB_PARAMETERS))
def test_every_lab_parameter_sweeps_alone(name):
    _compare("lab_glass_dry.toml", {name: LAB_VALUES[name][:2]}, _lab_cell)


def _subsets(parameters):
    return st.lists(st.sampled_from(sorted(parameters)), min_size=1, max_size=3, unique=True).filter(_allowed)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(names=_subsets(FAULT_VALUES), sizes=st.lists(st.integers(1, 3), min_size=3, max_size=3))
def test_any_fault_combination_matches_scalar(names, sizes):
    _compare("san_andreas_1906.toml", {n: FAULT_VALUES[n][:k] for n, k in zip(names, sizes)}, _fault_cell)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(names=_subsets(LAB_VALUES), sizes=st.lists(st.integers(1, 3), min_size=3, max_size=3))
def test_any_lab_combination_matches_scalar(names, sizes):
    _compare("lab_glass_dry.toml", {n: LAB_VALUES[n][:k] for n, k in zip(names, sizes)}, _lab_cell)


@pytest.mark.parametrize("values, message", [
    ({"zone_width": ["0 km"]}, "elastic-zone width must be positive"),
    ({"zone_width": ["-5 km", "10 km"]}, "elastic-zone width must be positive"),
    ({"mu_m": [0.7, 0.8]}, "is not below mu_so"),  # every cell: refused (some cells: flagged, below)
    ({"damping_ratio": [1.2]}, "damping ratio must lie in (-1, 1)"),
    ({"slip_rate": {"logspace": ["1 mm/yr", "100 mm/yr", 0]}}, "count must be at least 1"),
])
def test_sweeps_refuse_what_fault_refuses(values, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        sweep("san_andreas_1906.toml", **values)


def test_a_sweep_flags_only_the_cells_without_a_static_excess():
    """mu_m 0.5 and 0.7 against the 1906 scene's mu_so of 0.65: the first cell is predicted, the second flagged."""
    dataset = sweep("san_andreas_1906.toml", mu_m=[0.5, 0.7])
    assert dataset["outside_domain"].values.tolist() == [0, 1]
    slip = dataset["slip_per_event"].values
    assert np.isfinite(slip[0]) and np.isnan(slip[1])


@pytest.mark.parametrize("method", ["auto", "closed_form", "exact_cycle"])
def test_a_study_without_swept_dimensions_is_one_cell(method):
    """Found by the fuzzer: a 0-d grid with the exact cycle wrote into a scalar copy."""
    dataset = sweep("lab_glass_dry.toml", method=method)
    expected = solve(read_slider_scene("lab_glass_dry.toml").slider(), tolerance=1e-6).cycle
    assert float(dataset["slip_per_event"]) == pytest.approx(expected.slip_per_event, rel=1e-5)


RATE_STATE_VALUES = {
    "a": [0.005, 0.010, 0.02],
    "b": [0.0, 0.015, 0.012],
    "critical_slip": ["10 um", "8 mm", "20 cm"],
    "mu0": [0.6, 0.65, 0.7],
    "reference_speed": ["1 um/s", "1 mm/s", "1e-9 m/s"],
    "evolution": ["aging", "slip"],
    "shear_modulus": ["0.2e6 bar", "30 GPa", "32 GPa"],
    "zone_width": ["10 km", "20 km", "13 mi"],
    "normal_stress": ["300 bar", "50 MPa", "10 MPa"],
    "shear_stress": ["200 bar", "250 bar", "30 MPa"],
    "slip_rate": ["10 mm/yr", "30 mm/yr", "2 in/yr"],
    "rupture_length": ["100 km", "200 km", "270 mi"],
    "seismogenic_depth": ["10 km", "15 km", "12 km"],
    "density": ["2600 kg/m^3", "2800 kg/m^3", "3000 kg/m^3"],
    "shear_wave_speed": ["3 km/s", "3.5 km/s", "2.8 km/s"],
}


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(names=st.lists(st.sampled_from(sorted(RATE_STATE_VALUES)), min_size=1, max_size=4, unique=True),
       sizes=st.lists(st.integers(1, 3), min_size=4, max_size=4))
def test_every_rate_state_combination_gives_the_scalar_closed_form(names, sizes):
    """Any subset of a rate-and-state study's parameters: every cell's K / K_c and steady-state friction
    equal RateStateLaw's on that cell's fault, computed without grid code (issue 9's lesson)."""
    from faultslip.fault.scene import read_slider_scene as scene_of
    from faultslip.friction.rate_state import RateStateLaw
    from faultslip.units import to_si_scalar

    if {"normal_stress", "shear_stress"} <= set(names):
        return
    dims = {n: RATE_STATE_VALUES[n][:size] for n, size in zip(names, sizes)}
    out = sweep("san_andreas_1906_rate_state.toml", **dims)
    base = scene_of("san_andreas_1906_rate_state.toml")
    friction = base.tables["friction"]
    units = {"critical_slip": "length", "reference_speed": "speed", "shear_modulus": "pressure",
             "zone_width": "length", "normal_stress": "pressure", "shear_stress": "pressure", "slip_rate": "speed",
             "rupture_length": "length", "seismogenic_depth": "length", "density": "density",
             "shear_wave_speed": "speed"}

    def si(name, value):
        return value if name == "evolution" else to_si_scalar(value, units[name], name) if name in units \
            else float(value)

    for index in itertools.product(*(range(len(v)) for v in dims.values())):
        cell = {n: si(n, dims[n][i]) for n, i in zip(dims, index)}
        law = {k: cell.get(k, si(k, friction[k])) for k in ("a", "b", "critical_slip", "mu0", "reference_speed")}
        law = RateStateLaw(evolution=cell.get("evolution", "aging"), **law)
        modulus = cell.get("shear_modulus", 0.25e6 * 1e5)
        width = cell.get("zone_width", 13 * 1609.344)
        sigma = cell.get("normal_stress", cell.get("shear_stress", 250e5) / law.mu0)
        plate = cell.get("slip_rate", 2 * 0.0254 / (365.25 * 86400))
        got = out.isel({n: i for n, i in zip(dims, index)})
        k_c = sigma * (law.b - law.a) / law.critical_slip
        expected = modulus / width / k_c if k_c > 0 else np.inf
        assert float(got["stiffness_ratio"]) == pytest.approx(expected, rel=1e-12)
        assert float(got["steady_state_friction"]) == pytest.approx(float(law.steady_state(plate)), rel=1e-12)
