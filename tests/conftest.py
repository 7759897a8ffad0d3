"""Shared test helpers."""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import shutil
import subprocess
import tempfile

# a matplotlib cache of the run's own, set before matplotlib is imported and inherited by the xdist workers and
# the commands the tests start: a user's cache can name the fonts of a deleted environment, and plots then warn on
# stderr, which the front-door tests read (.ci/run sets its own; a caller's MPLCONFIGDIR is kept)
if "MPLCONFIGDIR" not in os.environ:
    os.environ["MPLCONFIGDIR"] = tempfile.mkdtemp(prefix="faultslip-tests-matplotlib-")
    atexit.register(shutil.rmtree, os.environ["MPLCONFIGDIR"], True)

import matplotlib  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

matplotlib.use("Agg")

# estimates follow the machine's speed (faultslip.io.machine); a test's must not, so every test process and the
# commands it starts take the machine the costs were anchored on (tests/capabilities/contract/test_machine_speed.py
# unsets it where the probe itself is tested)
os.environ.setdefault("FAULTSLIP_MACHINE_FACTOR", "1")
# and none adds its probes to the user's machine speed record (its own tests point it at a temporary file)
os.environ.setdefault("FAULTSLIP_MACHINE_RECORD", "off")

# CI is slower and must be deterministic; locally explore a little more.
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=100, deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")


def pytest_sessionstart(session):
    """On two cores or more, compile what a fresh environment compiles on first use, once, beside the tests
    (tests/warm_up.py says what and why): from pytest-xdist's controller, which only gathers the workers'
    results, or from a run in one process; FAULTSLIP_NO_WARM_UP=1 turns it off."""
    import sys

    from faultslip.io.processes import usable_cores

    if usable_cores() < 2 or os.environ.get("FAULTSLIP_NO_WARM_UP") or hasattr(session.config, "workerinput"):
        return
    script = os.path.join(os.path.dirname(__file__), "warm_up.py")
    session.config.warm_up = subprocess.Popen([sys.executable, script, str(os.getpid())],
                                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


@pytest.hookimpl(optionalhook=True)  # pytest-xdist's hook: a run without it (-p no:xdist) still starts
def pytest_xdist_auto_num_workers(config):
    """``-n auto``: a worker for each core this process may use (its CPU affinity, as faultslip counts them), not
    each of the machine's physical cores, which pytest-xdist counts where psutil is installed."""
    from faultslip.io.processes import usable_cores

    return usable_cores()


#: The files that take longest in CI (its --durations), handed out first. pytest-xdist hands a worker a file at a
#: time, by default the files with most tests first; the front door (a fresh venv, then every documented command:
#: five to six minutes, one test) came last and ran alone on one core while the other worker sat idle. The longest
#: first lets the other worker take the rest meanwhile, and the two end together. The order changes nothing a test
#: sees: every file runs in a process of its own (--dist loadfile).
SLOWEST_FIRST = ("tests/project/test_front_door.py", "tests/capabilities/contract/test_families.py",
                 "tests/capabilities/contract/test_models.py", "tests/models/vibration/test_averaging.py",
                 "tests/models/fault_3d/test_fault_3d.py", "tests/capabilities/studies/test_slurm.py",
                 "tests/capabilities/lab/test_raw_records.py", "tests/project/test_docs.py")


def pytest_configure(config):
    if hasattr(config.option, "loadscopereorder"):  # pytest-xdist's by-count order would override the one below
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(config, items):
    """The slowest files first (SLOWEST_FIRST), every other file after them in its usual order."""
    rank = {path: place for place, path in enumerate(SLOWEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))


def pytest_sessionfinish(session):
    process = getattr(session.config, "warm_up", None)
    if process is not None and process.poll() is None:
        process.kill()
    if process is not None:
        process.wait()


@pytest.fixture(autouse=True, scope="session")
def isolated_registry(tmp_path_factory):
    """Never read or write the user's real fit registry."""
    path = tmp_path_factory.mktemp("registry") / "fits.json"
    os.environ["FAULTSLIP_REGISTRY"] = str(path)
    yield path


class CliResult:
    def __init__(self, code, out, err):
        self.code, self.out, self.err = code, out, err

    @property
    def json(self):
        return json.loads(self.out)


@pytest.fixture
def cli(capsys):
    """Run ``faultslip ARGS`` in-process; return exit code, stdout, stderr."""
    from faultslip.cli.main import main

    def run(*args):
        try:
            code = main([str(a) for a in args])
        except SystemExit as exc:  # argparse exits
            code = exc.code
        captured = capsys.readouterr()
        return CliResult(code, captured.out, captured.err)

    return run


def load_benchmark(name: str, as_name: str | None = None):
    """benchmarks/<name>.py as a module, for tests that recompute what a benchmark writes.

    Its folder is on sys.path while it loads (the scripts import their neighbours, provenance among them) and
    sys.path is put back afterwards, whatever the script added: pool workers a later test spawns inherit sys.path,
    and with the clone on it would import faultslip from the clone's source instead of the installed package."""
    import importlib.util
    from pathlib import Path
    import sys

    folder = Path(__file__).resolve().parent.parent / "benchmarks"
    saved = list(sys.path)
    sys.path.insert(0, str(folder))
    try:
        spec = importlib.util.spec_from_file_location(as_name or f"benchmark_{name}", folder / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path[:] = saved
    return module


def modelled_seconds(printed: dict) -> float:
    """An ``--estimate --json``'s cost-model seconds, without the imports its process measured
    (:attr:`faultslip.io.budget.Estimate.modelled_seconds`, as the command prints it)."""
    return printed["seconds"]["value"] - printed.get("import_seconds", {"value": 0.0})["value"]


def assert_clean_error(result, *needles):
    """Exit status 2, one sentence on stderr naming the input, no traceback."""
    assert result.code == 2, (result.code, result.out, result.err)
    assert "Traceback" not in result.err
    lines = [line for line in result.err.strip().splitlines() if line]
    assert len(lines) == 1, result.err
    for needle in needles:
        assert needle.lower() in result.err.lower(), (needle, result.err)


@contextlib.contextmanager
def mounted_tmpfs(folder, size: str):
    """A tmpfs of ``size`` ("40k", "300k") mounted at ``folder`` (created), unmounted afterwards; the test is
    skipped where mounting is not allowed (it needs root, as CI has)."""
    folder.mkdir()
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)], capture_output=True)
    if made.returncode != 0:
        pytest.skip("a tmpfs cannot be mounted here (needs root); the full-disk cases need one")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], capture_output=True)


#: what differs from one run to the next: wall times (and the asperity sweep's per-cell seconds)
VOLATILE_NUMBERS = {"wall_time", "seconds", "posterior_seconds", "computing_time", "elapsed"}


def report_numbers(value, where=""):
    """Every number in a report's JSON, by its path, wall times left out: what the CLI/API equality tests compare."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() if key not in VOLATILE_NUMBERS
                for k, v in report_numbers(item, f"{where}.{key}").items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in report_numbers(item, f"{where}[{i}]").items()}
    return {where: value} if isinstance(value, (int, float)) and not isinstance(value, bool) else {}


def engine_command() -> str:
    """The OpenQuake engine's ``oq`` beside this interpreter (or on the path); the calling test skips without it."""
    import shutil
    import sys

    pytest.importorskip("openquake.engine", reason="the OpenQuake engine is not installed")
    oq = shutil.which("oq", path=os.path.dirname(sys.executable)) or shutil.which("oq")
    if oq is None:
        pytest.skip("the OpenQuake engine's 'oq' command is not on the path")
    return oq


def run_engine_job(job, folder) -> list:
    """Run a classical job with the engine (its data in ``folder``); the lines of the mean PGA curve it exports
    beside the job."""
    from pathlib import Path

    environment = dict(os.environ, OQ_DATADIR=str(Path(folder) / "oqdata"), OQ_DISTRIBUTE="no")
    run = subprocess.run([engine_command(), "engine", "--run", str(job), "--exports", "csv"], capture_output=True,
                         text=True, env=environment, timeout=600)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    curves = list(Path(job).parent.glob("hazard_curve-mean-PGA*.csv"))
    assert len(curves) == 1
    return curves[0].read_text().splitlines()



#: A scene of the test family tests/families/constant_friction (the contract's tests and the SLURM tests use it).
TEST_SCENE = """family = "constant_friction"
[slider]
stiffness = "1e5 N/m"
normal_load = "100 N"
mass = "1 kg"
platform_speed = "1 mm/s"
[friction]
static = 0.6
kinetic = 0.5
"""
