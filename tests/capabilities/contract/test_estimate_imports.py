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

import pytest

HEAVY = ("xarray", "dask", "dask.array", "pandas", "scipy.integrate", "scipy.optimize", "scipy.interpolate",
         "scipy.stats", "scipy.ndimage", "scipy.signal", "scipy.linalg", "scipy.sparse", "scipy.special",
         "scipy.fft", "numba", "rocket_fft", "matplotlib", "cutde", "obspy", "netCDF4", "psutil")

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
