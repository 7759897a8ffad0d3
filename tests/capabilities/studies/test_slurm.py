"""Studies on a real batch system (issue 43, item 8): a single-node SLURM cluster started here, worker jobs
submitted by dask-jobqueue's SLURMCluster (``faultslip sweep --scheduler slurm``), a job cancelled mid-study, and
the failure ledger with ``--retry-failed``.

The cluster is Debian's ``slurm-wlm`` with ``munge``: ``slurmctld`` and ``slurmd`` on this machine, their
configuration, state and logs in a temporary folder, on free ports, started by the ``slurm`` fixture and stopped
after the module (``.ci/run`` installs the two packages where apt can). Without them, or without root (slurmd
runs jobs as their users), the SLURM tests skip and say why; the ledger's tests run everywhere.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from faultslip import contract
from faultslip.io import gate
from faultslip.io.netcdf import CHECKSUM_ATTRIBUTE
from conftest import TEST_SCENE

ROOT = Path(__file__).resolve().parents[3]
TESTS = Path(__file__).resolve().parents[2]
DAEMONS = ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "scancel", "squeue", "sinfo")

SCENE = TEST_SCENE.replace('"constant_friction"', '"slow_friction"')  # the same slider, slowly
STUDY = """[study]
name = "slow friction"
base = "slow.toml"
[sweep]
static_friction = [0.6, 0.65, 0.7, 0.75, 0.8, 0.85]
platform_speed = ["1 mm/s", "2 mm/s"]
"""


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _why_no_slurm() -> str | None:
    missing = [name for name in DAEMONS if shutil.which(name) is None]
    if missing:
        return f"SLURM is not installed here (no {', '.join(missing)}; Debian's slurm-wlm and munge provide them)"
    if os.geteuid() != 0:
        return "slurmd runs jobs as their users and needs root to start here"
    import importlib.util

    if importlib.util.find_spec("dask_jobqueue") is None:
        return "dask-jobqueue is not installed (pip install 'faultslip[dask]')"
    return None


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    """A single-node SLURM cluster on this machine: (its folder, the environment that reaches it)."""
    reason = _why_no_slurm()
    if reason:
        pytest.skip(reason)
    folder = tmp_path_factory.mktemp("slurm")
    for name in ("state", "spool", "munge", "jobs"):
        (folder / name).mkdir()
    host = socket.gethostname().split(".")[0]
    memory = int(int(Path("/proc/meminfo").read_text().split()[1]) / 1024 * 0.8)
    socket_path = folder / "munge" / "munge.socket"
    config = folder / "slurm.conf"
    config.write_text("\n".join([
        "ClusterName=faultslip", f"SlurmctldHost={host}(127.0.0.1)", "SlurmUser=root", "SlurmdUser=root",
        "AuthType=auth/munge", f"AuthInfo=socket={socket_path}", f"StateSaveLocation={folder / 'state'}",
        f"SlurmdSpoolDir={folder / 'spool'}", f"SlurmctldPidFile={folder / 'slurmctld.pid'}",
        f"SlurmdPidFile={folder / 'slurmd.pid'}", f"SlurmctldLogFile={folder / 'slurmctld.log'}",
        f"SlurmdLogFile={folder / 'slurmd.log'}", "ProctrackType=proctrack/linuxproc", "TaskPlugin=task/none",
        "SchedulerType=sched/backfill", "SelectType=select/cons_tres", "SelectTypeParameters=CR_Core",
        "ReturnToService=2", "MpiDefault=none", "JobAcctGatherType=jobacct_gather/none",
        "AccountingStorageType=accounting_storage/none", f"SlurmctldPort={_free_port()}",
        f"SlurmdPort={_free_port()}", "KillWait=2", "MinJobAge=5",
        f"NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count()} RealMemory={memory} State=UNKNOWN",
        "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP", ""]))
    environment = dict(os.environ, SLURM_CONF=str(config))
    key = folder / "munge" / "munge.key"
    subprocess.run(["mungekey", "--create", f"--keyfile={key}"], check=True, capture_output=True)
    key.chmod(0o600)
    started = []
    try:
        for command in (["munged", f"--socket={socket_path}", f"--key-file={key}", "--force",
                         f"--pid-file={folder / 'munge' / 'munged.pid'}", f"--log-file={folder / 'munge' / 'log'}",
                         f"--seed-file={folder / 'munge' / 'seed'}"],
                        ["slurmctld", "-f", str(config)], ["slurmd", "-f", str(config)]):
            subprocess.run(command, check=True, capture_output=True, env=environment, timeout=30)
            started.append(command[0])
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            state = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True, env=environment)
            if state.stdout.strip() == "idle":
                break
            time.sleep(0.3)
        else:
            pytest.skip(f"the SLURM node did not come up ({state.stdout.strip() or state.stderr.strip()})")
        yield folder, environment
    finally:
        subprocess.run(["scancel", "--full", "-u", "root"], capture_output=True, env=environment)
        for pid_file in ("slurmd.pid", "slurmctld.pid", "munge/munged.pid"):
            path = folder / pid_file
            if path.exists():
                try:
                    os.kill(int(path.read_text().split()[0]), signal.SIGTERM)
                except (ProcessLookupError, ValueError):
                    pass


@pytest.fixture
def slow_family(tmp_path, monkeypatch):
    """The slow-friction test family declared, its scene and study written, its cells logged to ``cells.log``;
    workers started elsewhere (SLURM jobs) import it from tests/ through PYTHONPATH."""
    contract.declare("slow_friction", "families.slow_friction.family")
    (tmp_path / "slow.toml").write_text(SCENE, encoding="utf-8")
    (tmp_path / "study.toml").write_text(STUDY, encoding="utf-8")
    log = tmp_path / "cells.log"
    monkeypatch.setenv("FAULTSLIP_TEST_CELL_LOG", str(log))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(TESTS), os.environ.get("PYTHONPATH")])))
    monkeypatch.setenv("FAULTSLIP_FAMILIES", "slow_friction=families.slow_friction.family")
    yield tmp_path, log
    contract.DECLARATIONS.pop("slow_friction", None)
    contract.FAMILIES.pop("slow_friction", None)


def _sweep(*arguments, env=None, check=True):
    """``faultslip sweep ... --json`` in its own process (as a user runs it); (exit code, JSON or stderr)."""
    result = subprocess.run([sys.executable, "-m", "faultslip.cli", "sweep", *map(str, arguments), "--json"],
                            capture_output=True, text=True, timeout=600, env=env, cwd=ROOT)
    if check:
        assert result.returncode == 0, result.stderr
    return result


def _same_results(left: Path, right: Path) -> None:
    """Every variable, coordinate and attribute of two study files (or Zarr stores) bit for bit (but the run's
    history)."""
    def shown(attrs, skip=()):  # repr: a NaN fill value equals itself
        return {key: repr(value) for key, value in attrs.items() if key not in skip}

    def opened(path):
        return xr.open_zarr(path, decode_cf=False) if path.suffix == ".zarr" else xr.open_dataset(path, decode_cf=False)

    with opened(left) as a, opened(right) as b:
        assert set(a.variables) == set(b.variables)
        for name in a.variables:
            assert a[name].values.tobytes() == b[name].values.tobytes(), name
            assert shown(a[name].attrs) == shown(b[name].attrs), name
        # the checksum covers history and source too
        skip = ("history", "source", CHECKSUM_ATTRIBUTE)
        assert shown(a.attrs, skip) == shown(b.attrs, skip)


def _cells(log: Path) -> list[tuple[str, str, str]]:
    """(event, cell, SLURM job) of every line of the cell log."""
    rows = [line.split() for line in log.read_text().splitlines()] if log.exists() else []
    return [(event, f"{static} {speed}", job) for event, static, speed, job in rows]


# --- the failure ledger (everywhere) ----------------------------------------------------------------------

@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_failed_cells_are_listed_and_only_they_are_retried(slow_family, suffix):
    """Cells whose solver fails keep NaN, the sweep exits 1 naming its ledger, the ledger lists each failed cell
    with its indices, values and reason; --retry-failed computes those cells and no other, and the file (or
    store) then equals a run that never failed, bit for bit."""
    folder, log = slow_family
    environment = dict(os.environ, FAULTSLIP_TEST_FAIL_ABOVE="0.77")
    out = folder / f"out{suffix}"
    failed = _sweep(folder / "study.toml", "-o", out, "--workers", "2", "--chunks", "3", env=environment,
                    check=False)
    assert failed.returncode == 1, failed.stderr
    assert "4 cells failed" in failed.stderr and "--retry-failed" in failed.stderr
    ledger = json.loads((folder / f"out{suffix}.failed.json").read_text())
    assert ledger["failed_cells"] == 4 and ledger["dimensions"] == ["static_friction", "platform_speed"]
    assert {(c["index"]["static_friction"], c["index"]["platform_speed"]) for c in ledger["cells"]} == \
        {(4, 0), (4, 1), (5, 0), (5, 1)}
    assert all("fails above static friction 0.77" in c["reason"] for c in ledger["cells"])
    with (xr.open_zarr(out) if suffix == ".zarr" else xr.open_dataset(out)) as written:
        assert np.isnan(written["slip_per_event"].values[4:]).all()
        assert np.isfinite(written["slip_per_event"].values[:4]).all()
    log.unlink()
    intact_ledger = (folder / f"out{suffix}.failed.json").read_text()
    edited = json.loads(intact_ledger) | {"cells": ledger["cells"][1:], "failed_cells": 3}  # one failed cell dropped
    (folder / f"out{suffix}.failed.json").write_text(json.dumps(edited))
    refused = _sweep(folder / "study.toml", "-o", out, "--retry-failed", check=False)
    assert refused.returncode == 2 and "does not match the checksum" in refused.stderr, refused.stderr
    (folder / f"out{suffix}.failed.json").write_text(intact_ledger)
    if suffix == ".nc":  # the file is trusted only where it matches the checksum written with it
        intact = out.read_bytes()
        with netCDF4.Dataset(out, "a") as nc:
            nc.setncattr("title", nc.getncattr("title") + " (edited)")
        refused = _sweep(folder / "study.toml", "-o", out, "--retry-failed", check=False)
        assert refused.returncode == 2 and "does not match the checksum" in refused.stderr, refused.stderr
        assert not _cells(log)  # refused before any cell ran
        out.write_bytes(intact)
    retried = _sweep(folder / "study.toml", "-o", out, "--retry-failed")
    summary = json.loads(retried.stdout)
    assert (summary["retried"], summary["recovered"], summary["still_failed"]) == (4, 4, 0)
    assert not (folder / f"out{suffix}.failed.json").exists()
    assert sorted(cell for event, cell, _ in _cells(log) if event == "start") == \
        ["0.8 0.001", "0.8 0.002", "0.85 0.001", "0.85 0.002"]  # the failed cells, and nothing else
    clean = folder / f"clean{suffix}"
    _sweep(folder / "study.toml", "-o", clean, "--workers", "1")
    _same_results(out, clean)


def test_retry_failed_is_refused_in_one_sentence(slow_family, cli):
    from conftest import assert_clean_error

    folder, _ = slow_family
    assert_clean_error(cli("sweep", folder / "study.toml", "-o", folder / "none.nc", "--retry-failed"),
                       "does not exist")
    _sweep(folder / "study.toml", "-o", folder / "done.nc", "--workers", "1")
    assert_clean_error(cli("sweep", folder / "study.toml", "-o", folder / "done.nc", "--retry-failed"),
                       "no failure ledger")
    other = {"fingerprint": "another", "cells": []}
    (folder / "done.nc.failed.json").write_text(json.dumps(other))  # no checksum: edited, or of an older faultslip
    assert_clean_error(cli("sweep", folder / "study.toml", "-o", folder / "done.nc", "--retry-failed"),
                       "does not match the checksum")
    (folder / "done.nc.failed.json").write_text(json.dumps(other | {"checksum": gate.json_checksum(other)}))
    assert_clean_error(cli("sweep", folder / "study.toml", "-o", folder / "done.nc", "--retry-failed"),
                       "does not belong to this study")


def test_a_family_declared_in_the_environment_reaches_a_process_and_a_bad_entry_is_one_sentence(slow_family):
    folder, _ = slow_family
    ran = subprocess.run([sys.executable, "-m", "faultslip.cli", "run", str(folder / "slow.toml"), "--json"],
                         capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert ran.returncode == 0 and json.loads(ran.stdout)["slip_per_event"]["value"] == pytest.approx(2e-4), ran.stderr
    bad = subprocess.run([sys.executable, "-m", "faultslip.cli", "run", str(folder / "slow.toml")], capture_output=True,
                         text=True, timeout=120, cwd=ROOT, env=dict(os.environ, FAULTSLIP_FAMILIES="slow_friction"))
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and len(bad.stderr.strip().splitlines()) == 1
    assert "name=package.module" in bad.stderr


# --- on SLURM ---------------------------------------------------------------------------------------------

def test_a_2d_study_and_a_closed_form_sweep_on_slurm_match_one_process(slurm, tmp_path):
    """Both through ``--scheduler slurm`` (two worker jobs submitted by dask-jobqueue): the same bits as in this
    process. And ``reproduce --scheduler slurm`` spot-checks two cells of the closed-form study's file there (the
    whole reproduction runs as the sweep does: tests/capabilities/studies/test_distributed.py), and finds them the
    same."""
    _, environment = slurm
    fault_2d = tmp_path / "fault_2d.toml"
    fault_2d.write_text('[study]\nname = "2-D on SLURM"\nbase = "fault_2d_small.toml"\n[sweep]\n'
                        'critical_slip = ["20 mm", "30 mm"]\n', encoding="utf-8")
    for name, study, chunks in (("fault_2d", fault_2d, "1"), ("closed_form", ROOT / "configs" / "study_spring_slider.toml",
                                                              "2000")):
        local, remote = tmp_path / f"{name}_local.nc", tmp_path / f"{name}_slurm.nc"
        _sweep(study, "-o", local, "--workers", "1", "--chunks", chunks, env=environment)
        summary = json.loads(_sweep(study, "-o", remote, "--scheduler", "slurm", "--workers", "2", "--chunks", chunks,
                                    env=environment).stdout)
        assert summary["executor"].startswith("SLURM through dask-jobqueue"), summary
        _same_results(local, remote)
    from faultslip.studies.grid import load_study

    cells = load_study(ROOT / "configs" / "study_spring_slider.toml").size
    again = subprocess.run([sys.executable, "-m", "faultslip.cli", "reproduce", str(remote), "--cells", "2", "--seed",
                            "3", "--scheduler", "slurm", "--workers", "2", "--json"], capture_output=True, text=True,
                           timeout=600, env=environment, cwd=ROOT)
    assert again.returncode == 0, again.stderr
    report = json.loads(again.stdout)
    assert report["matches"] and report["executor"].startswith("SLURM through dask-jobqueue"), report
    assert report["cells"] == 2 and report["of_cells"] == cells and report["sample_seed"] == 3, report
    assert not subprocess.run(["squeue", "-h"], capture_output=True, text=True, env=environment).stdout.strip(), \
        "the study's worker jobs outlived it"
    assert not list(ROOT.glob("slurm-*.out")), "the worker jobs' logs belong in a log folder, not the working folder"


def test_a_cancelled_job_costs_only_the_cells_it_held(slurm, slow_family):
    """Twelve 0.4-second cells, one a block, on two SLURM worker jobs; one job is cancelled (scancel) once three
    cells are done. The study finishes with every cell, bit for bit what one process computes; only cells the
    cancelled job had started are computed twice, and no more of them than were in flight."""
    _, environment = slurm
    folder, log = slow_family
    environment = dict(environment, FAULTSLIP_TEST_CELL_SECONDS="0.4", PYTHONPATH=os.environ["PYTHONPATH"],
                       FAULTSLIP_TEST_CELL_LOG=str(log), FAULTSLIP_FAMILIES=os.environ["FAULTSLIP_FAMILIES"])
    out = folder / "slurm.nc"
    command = [sys.executable, "-m", "faultslip.cli", "sweep", str(folder / "study.toml"), "-o", str(out),
               "--scheduler", "slurm", "--workers", "2", "--chunks", "1", "--json"]
    sweep = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=environment,
                             cwd=ROOT)
    try:
        deadline = time.monotonic() + 120
        while sum(event == "end" for event, _, _ in _cells(log)) < 3:
            assert time.monotonic() < deadline and sweep.poll() is None, "the study did not start its cells"
            time.sleep(0.1)
        running = {job for event, _, job in _cells(log) if event == "start"}
        victim = sorted(running)[0]
        subprocess.run(["scancel", victim], check=True, env=environment)
        stdout, stderr = sweep.communicate(timeout=300)
    finally:
        if sweep.poll() is None:
            sweep.kill()
    assert sweep.returncode == 0, stderr
    rows = _cells(log)
    started = [cell for event, cell, _ in rows if event == "start"]
    finished = {cell for event, cell, _ in rows if event == "end"}
    assert len(finished) == 12
    twice = {cell for cell in started if started.count(cell) > 1}
    on_victim = {cell for event, cell, job in rows if event == "start" and job == victim}
    assert twice <= on_victim, (twice, victim, rows)
    assert len(started) - 12 <= 3  # at most the window of blocks in flight
    clean = folder / "clean.nc"
    _sweep(folder / "study.toml", "-o", clean, "--workers", "1")
    _same_results(out, clean)
