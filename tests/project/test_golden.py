"""Golden ``--json`` outputs of every bundled scene and command: a refactor must not change them.

Regenerate on purpose (and say why in the commit) with::

    FAULTSLIP_REGENERATE_GOLDEN=1 pytest tests/project/test_golden.py

Numbers are compared to a relative tolerance that comes from the algorithm that computed them, not
from the last machine's digits: 1e-9 for closed forms and integrations run far tighter than that,
and 100 times the least-squares tolerance for fits (the fit stops once a step moves the
parameters by less than its tolerance, so another BLAS kernel, processor or scipy release moves
the result by about that, times the problem's conditioning: measured 1.6e-8 between two
machines). Texts are compared exactly. Wall times, dates and paths are left out.
"""

import json
import math
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).resolve().parents[1] / "golden"
CONFIGS = ROOT / "configs"
SCENES = sorted(p.name for p in CONFIGS.glob("*.toml") if "[scene]" in p.read_text(encoding="utf-8"))
from faultslip.friction.fitting import LEAST_SQUARES_TOLERANCE
from faultslip.lab.records import FIT_RESOLUTION

#: Relative tolerance of each command's numbers, where it is not DEFAULT_TOLERANCE (see the module).
DEFAULT_TOLERANCE = 1e-9
#: decay_record is curve_fit's (MINPACK's step tolerance 1.49e-8, faultslip.lab.records.FIT_RESOLUTION) times
#: the conditioning: its values moved by 1e-11 and its round-off standard errors by 2.5x between two machines.
TOLERANCE = {"fit_example": 100 * LEAST_SQUARES_TOLERANCE, "decay_record": 10 * FIT_RESOLUTION}
#: An estimated relative error is the difference of two answers over one: another machine's round-off in either
#: answer moves it by that much however small the error is (the time-of-stick run's 1.0003e-10 moved by 1.3e-16
#: between two machines; the closed forms' estimates are round-off itself, 7e-18 to 2e-14). Such fields are
#: also compared to this absolute floor: four orders above that round-off, and a real change of an estimate of
#: 1e-10 or more still fails (test_an_error_estimate_is_compared_to_its_round_off_floor).
ERROR_ESTIMATES, ESTIMATE_FLOOR = {"estimated_relative_error", "numerical_error"}, 1e-12
VOLATILE = {"wall_time", "seconds", "created", "output", "files", "date", "history"}

COMMANDS = {f"run_{name[:-5]}": ["run", name, "--json"] for name in SCENES}
COMMANDS.update({
    "fault_1906_flags": ["fault", "--lithology", "granodiorite_water", "--shear-modulus", "0.25e6 bar",
                         "--zone-width", "13 mi", "--shear-stress", "250 bar", "--slip-rate", "2 in/yr",
                         "--rupture-length", "270 mi", "--depth", "12 km", "--json"],
    "fault_granite_inverse": ["fault", "--lithology", "granite", "--zone-width", "13 mi", "--shear-stress",
                              "250 bar", "--slip-rate", "2 in/yr", "--mu-so", "0.65", "--observed-slip", "21 ft",
                              "--json"],
    "fault_radiation": ["fault", "--lithology", "pyrite", "--zone-width", "10 km", "--normal-stress", "50 MPa",
                        "--slip-rate", "30 mm/yr", "--radiation-damping", "--json"],
    "materials": ["materials", "--json"],
    "methods": ["methods", "--json"],
    "cycle_glass": ["cycle", "lab_glass_dry.toml", "--loading-rate", "0.1 1/s", "--json"],
    "cycle_glass_high_rate": ["cycle", "lab_glass_dry.toml", "--loading-rate", "1000 1/s", "--json"],
    "critical_glass": ["critical", "--preset", "glass_dry", "--damping-ratio", "0.1", "--json"],
    "decay_numbers": ["decay", "--stiffness", "70.5 lbf/in", "--ratio", "1.225", "--cycles", "10", "--frequency",
                      "19.9 Hz", "--json"],
    "decay_record": ["decay", str(CONFIGS / "example_decay_record.csv"), "--stiffness", "12346 N/m", "--json"],
    "fit_example": ["fit", str(CONFIGS / "example_friction_data.csv"), "--bootstrap", "50", "--seed", "1", "--json"],
    "record_example": ["record", str(CONFIGS / "example_record.csv"), "--stiffness", "1.94e4 lbf/in",
                       "--normal-load", "137.8 lbf", "--json"],
    "simulate_glass": ["simulate", "lab_glass_dry.toml", "--cycles", "5", "--json"],
    "simulate_cameron": ["simulate", "lab_steel_dry_time_of_stick.toml", "--cycles", "20", "--json"],
})


def _strip(value):
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k not in VOLATILE}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    if isinstance(value, str) and (str(ROOT) in value or "/tmp" in value):
        return "<path>"
    return value


def _same(a, b, where="", tolerance=DEFAULT_TOLERANCE) -> list:
    if isinstance(a, dict) and isinstance(b, dict):
        problems = [f"{where}: keys {sorted(set(a) ^ set(b))}"] if set(a) != set(b) else []
        for key in set(a) & set(b):
            problems += _same(a[key], b[key], f"{where}.{key}", tolerance)
        return problems
    floor = ESTIMATE_FLOOR if where.rsplit(".", 1)[-1] in ERROR_ESTIMATES else 1e-300
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} items against {len(b)}"]
        return [p for i, (x, y) in enumerate(zip(a, b)) for p in _same(x, y, f"{where}[{i}]", tolerance)]
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if math.isclose(a, b, rel_tol=tolerance, abs_tol=floor) or (math.isnan(a) and math.isnan(b)):
            return []
        return [f"{where}: {a!r} against golden {b!r}"]
    return [] if a == b else [f"{where}: {a!r} against golden {b!r}"]


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_json_output_matches_its_golden_file(name, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a bare scene name means the bundled scene
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "fits.json"))  # no user fits
    result = cli(*COMMANDS[name])
    assert result.code == 0, result.err
    got = _strip(json.loads(result.out))
    path = GOLDEN / f"{name}.json"
    if os.environ.get("FAULTSLIP_REGENERATE_GOLDEN"):
        GOLDEN.mkdir(exist_ok=True)
        path.write_text(json.dumps(got, indent=1, sort_keys=True) + "\n", encoding="utf-8")
        return
    assert path.exists(), f"no golden file for {name}: run with FAULTSLIP_REGENERATE_GOLDEN=1"
    problems = _same(got, json.loads(path.read_text(encoding="utf-8")), tolerance=TOLERANCE.get(name, DEFAULT_TOLERANCE))
    assert not problems, "\n".join(problems[:20])


def test_an_error_estimate_is_compared_to_its_round_off_floor():
    """Round-off moves an estimated error by ~1e-16 whatever its size: that passes; a change of the estimate
    itself, or the same small move in an answer, does not."""
    got = {"estimated_relative_error": 1.0003229695439025e-10}
    golden = {"estimated_relative_error": 1.0003242718404504e-10}
    assert not _same(got, golden)
    assert _same({"estimated_relative_error": 3e-10}, golden)
    assert _same({"recurrence_period": 1.0003229695439025e-10}, {"recurrence_period": 1.0003242718404504e-10})
    assert _same({"estimated_relative_error": 2e-12}, {"estimated_relative_error": 1e-14})
