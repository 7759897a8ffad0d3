"""Every family's estimate counts the imports its run makes (faultslip.io.budget.Estimate.imports).

A short run's CPU is mostly its lazy imports (xarray and the dask.array its first Dataset imports, scipy's
integrators, numba's extensions): an estimate that left them out missed a lab slider's command several times over
(benchmarks/command_estimates.py). Each case runs in a fresh interpreter: the estimate imports what it declares
(budget.with_imports), and the run that follows must import no heavy module beyond it. The 2-D and 3-D faults are
not here: their estimates count a fresh process's first run as a whole (FAULT_2D_FIRST_RUN_SECONDS, measured by
benchmarks/first_run.py).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

CONFIGS = Path(__file__).resolve().parents[3] / "configs"
HEAVY = ("xarray", "dask", "dask.array", "pandas", "scipy.integrate", "scipy.optimize", "scipy.interpolate",
         "scipy.stats", "scipy.ndimage", "scipy.signal", "scipy.linalg", "scipy.sparse", "scipy.special",
         "scipy.fft", "numba", "rocket_fft", "matplotlib", "cutde", "obspy", "netCDF4", "psutil", "distributed")

PROBE = r"""
import json, sys
import faultslip.cli.main  # what the command imports to start
from faultslip import models
scene, action, options, heavy = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), json.loads(sys.argv[4])
estimate = models.estimate(scene, action, **options)
def loaded():
    return bool(getattr(sys.modules.get("numba.core.entrypoints"), "_already_initialized", False))
before, extensions = {m for m in heavy if m in sys.modules}, loaded()
(models.run if action == "run" else models.simulate)(scene, **options)
after = {m for m in heavy if m in sys.modules}
print(json.dumps({"imported": sorted(after - before), "extensions": loaded() and not extensions,
                  "declared": list(estimate.imports)}))
"""

CASES = [
    ("lab_glass_dry.toml", "run", {}),  # closed form: nothing
    ("lab_glass_dry.toml", "run", {"method": "event_driven_DOP853"}),
    ("lab_steel_dry_time_of_stick.toml", "run", {}),  # the exact map's analytic simulation
    ("lab_steel_dry_polynomial.toml", "run", {}),
    ("lab_glass_dry.toml", "simulate", {"cycles": 5}),
    ("san_andreas_1906.toml", "run", {}),
    ("rsf_velocity_step.toml", "run", {}),  # compiled: numba's extensions
    ("rsf_block_bp1.toml", "run", {"model": "one_slider"}),
    ("rsf_block_bp1.toml", "simulate", {}),
    ("rough_surface_seed000.toml", "run", {}),
    ("nanoscale_seed001.toml", "run", {}),
    ("nanoscale_seed001.toml", "run", {"method": "nanoscale_linear_stability"}),
    ("asperity_seed004.toml", "run", {"method": "asperity_wavelength"}),
    ("asperity_seed004.toml", "run", {"method": "asperity_measured_wavelength"}),
    ("asperity_seed004.toml", "run", {"method": "asperity_quasistatic"}),
    ("vibration_seed002.toml", "run", {}),
    ("vibration_seed002.toml", "run", {"method": "quasi_harmonic_integration"}),
    ("vibration_seed002.toml", "simulate", {}),
    ("spring_chain_small.toml", "run", {}),
]


@pytest.mark.parametrize("scene, action, options", CASES,
                         ids=[f"{s}-{a}-{'-'.join(map(str, o.values())) or 'default'}" for s, a, o in CASES])
def test_a_run_imports_nothing_its_estimate_did_not_count(scene, action, options):
    done = subprocess.run([sys.executable, "-c", PROBE, scene, action, json.dumps(options), json.dumps(HEAVY)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert found["imported"] == [], f"the run imported {found['imported']}, its estimate declared {found['declared']}"
    assert not found["extensions"], f"the run loaded numba's extensions, its estimate declared {found['declared']}"


COMMAND_PROBE = r"""
import json, sys
from faultslip.cli.main import main
command, heavy = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert main([*command, "--estimate", "--json"]) == 0
def loaded():
    return bool(getattr(sys.modules.get("numba.core.entrypoints"), "_already_initialized", False))
before, extensions = {m for m in heavy if m in sys.modules}, loaded()
assert main(command) == 0
after = {m for m in heavy if m in sys.modules}
print(json.dumps({"imported": sorted(after - before), "extensions": loaded() and not extensions}))
"""

#: the example studies of the vectorised cells (seed law, rate and state) and of cell-by-cell families (PerCell,
#: whose imports are their run's: the nanoscale and asperity studies, 6 and 12 s of cells, add no other path), and
#: both maps, and a simulation written to netCDF (xarray's writer imports distributed); the discretised faults'
#: first run is counted whole
COMMANDS = [["sweep", study] for study in ("study_spring_slider.toml", "study_lab_glass.toml", "study_rate_state.toml",
                                           "study_rate_state_slider.toml", "study_vibration.toml",
                                           "study_rough_surface.toml", "study_spring_chain.toml")] + [
    ["map", "san_andreas_map.toml"], ["map", "san_andreas_map_rate_state.toml"],
    ["simulate", "lab_glass_dry.toml", "--cycles", "5"]]


@pytest.mark.parametrize("command", COMMANDS, ids=[" ".join(c) for c in COMMANDS])
def test_a_sweep_or_map_imports_nothing_its_estimate_did_not_count(command, tmp_path):
    """The same for a sweep's and a map's command: its estimate (faultslip ... --estimate) imports what it counts,
    and the command that follows, writing its file, imports nothing more."""
    full = [*command, "-o", str(tmp_path / "out.nc")]
    done = subprocess.run([sys.executable, "-c", COMMAND_PROBE, json.dumps(full), json.dumps(HEAVY)],
                          capture_output=True, text=True, timeout=900, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert found["imported"] == [], f"the command imported {found['imported']} that its estimate did not count"
    assert not found["extensions"], "the command loaded numba's extensions, which its estimate did not count"


def test_imports_are_counted_once_and_a_missing_one_fails_nothing():
    """with_imports adds what it measured to the estimate; asked again, it finds the modules imported and adds
    nothing. A module not installed here is left to the run, which names it where it needs it: the estimate does
    not fail on it."""
    from faultslip.io import budget

    estimate = budget.Estimate("a run", seconds=1.0, imports=("faultslip_no_such_module", "json"))
    once = budget.with_imports(estimate)
    assert once.seconds == pytest.approx(1.0 + once.import_seconds, rel=1e-12) and once.import_seconds >= 0
    assert once.modelled_seconds == pytest.approx(1.0, rel=1e-12)  # the cost model's, without the imports
    twice = budget.with_imports(once)
    assert (twice.seconds, twice.import_seconds, twice.notes) == (once.seconds, once.import_seconds, once.notes)
    report = twice.report(started=5.0).to_dict()
    # the command's start is what it used less the run's imports, which its seconds already hold
    assert report["command_seconds"]["value"] == pytest.approx(twice.seconds + 5.0 - twice.import_seconds, rel=1e-12)


def test_a_stiff_faults_cycles_count_lsodas_import(tmp_path):
    """A fault whose rupture is stiff (K / K_c 2.8e-3: BP1 with a / b 0.46 and D_c 0.34 mm) steps its cycles by
    LSODA, which imports scipy.integrate (0.1-0.2 s): its simulation's estimate had declared the Dataset alone,
    and came to a fifth of the CPU used. BP1 itself (dopri5) imports no integrator and declares none."""
    text = (CONFIGS / "rsf_block_bp1.toml").read_text(encoding="utf-8")
    stiff = text.replace("a = 0.010", "a = 0.0069").replace('critical_slip = "8 mm"', 'critical_slip = "0.34 mm"')
    assert stiff != text
    (tmp_path / "stiff.toml").write_text(stiff, encoding="utf-8")
    for scene, integrator in ((tmp_path / "stiff.toml", True), ("rsf_block_bp1.toml", False)):
        done = subprocess.run([sys.executable, "-c", PROBE, str(scene), "simulate", "{}", json.dumps(HEAVY)],
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stderr[-2000:]
        found = json.loads(done.stdout.strip().splitlines()[-1])
        assert found["imported"] == [], (found["imported"], found["declared"])
        assert ("scipy.integrate" in found["declared"]) == integrator, found["declared"]
