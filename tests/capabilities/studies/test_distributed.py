"""Scale-out on a real dask cluster: a scheduler and workers started as separate processes.

The test starts ``dask scheduler`` and ``dask worker`` (two worker processes) on localhost, runs
``faultslip sweep --scheduler ADDRESS --format zarr`` against them, and checks that every
variable is bit-identical to the same study run in one process, and that the workers, not the
client, wrote the chunks. The Zarr store is then converted to netCDF and reproduced.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

pytest.importorskip("distributed")
pytest.importorskip("zarr")

STUDY = """
[study]
name = "distributed"
base = "san_andreas_1906.toml"

[sweep]
slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 40] }
zone_width = { linspace = ["5 km", "30 km", 25] }
lithology = ["granodiorite", "black_marble", "pyrite_dry"]
damping_ratio = [0.0, 0.1]
"""


def _start(arguments, log):
    return subprocess.Popen([sys.executable, "-m", *arguments], stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)


def _stop(process):
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


@pytest.fixture
def cluster(tmp_path):
    """The address of a scheduler with two single-threaded worker processes, all on localhost."""
    from distributed import Client

    scheduler_file = tmp_path / "scheduler.json"
    log = open(tmp_path / "cluster.log", "w")
    scheduler = _start(["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                        "--scheduler-file", str(scheduler_file)], log)
    workers = None
    try:
        deadline = time.time() + 60
        while not scheduler_file.exists() and time.time() < deadline:
            assert scheduler.poll() is None, (tmp_path / "cluster.log").read_text()
            time.sleep(0.1)
        address = json.loads(scheduler_file.read_text())["address"]
        workers = _start(["distributed.cli.dask_worker", "--scheduler-file", str(scheduler_file), "--nworkers", "2",
                          "--nthreads", "1", "--no-dashboard", "--local-directory", str(tmp_path / "workers")], log)
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(2, timeout=60)
            worker_pids = set(client.run(os.getpid).values())
        yield address, worker_pids
    finally:
        if workers is not None:
            _stop(workers)
        _stop(scheduler)
        log.close()


def _sweep(*arguments):
    result = subprocess.run([sys.executable, "-m", "faultslip.cli", "sweep", *arguments, "--json"],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def _raw(path):
    return xr.open_zarr(path, decode_cf=False)


def test_sweep_on_a_real_cluster_is_bit_identical_to_one_process(cluster, tmp_path):
    address, _ = cluster
    study = tmp_path / "study.toml"
    study.write_text(STUDY)
    local, remote = tmp_path / "local.zarr", tmp_path / "remote.zarr"
    _sweep(str(study), "-o", str(local), "--workers", "1", "--chunks", "500")
    summary = _sweep(str(study), "-o", str(remote), "--scheduler", address, "--chunks", "500")
    assert summary["executor"] == f"dask cluster at {address}" and summary["blocks"] > 4
    with _raw(local) as a, _raw(remote) as b:
        assert set(a.variables) == set(b.variables) and a.attrs.keys() == b.attrs.keys()
        for name in a.variables:
            left, right = a[name].values, b[name].values
            assert left.dtype == right.dtype and left.shape == right.shape
            if left.dtype.kind == "f":  # the same bits, NaN payloads included
                assert left.tobytes() == right.tobytes(), name
            else:
                assert np.array_equal(left, right), name
            assert a[name].attrs.keys() == b[name].attrs.keys()

    # the workers wrote the chunks: both worker processes ran write_zarr_block tasks (each returns
    # only its cell count to the client; dask names each by worker_task, which runs it listing failed cells)
    from distributed import Client

    with Client(address, timeout="30s") as client:
        ran = client.run(lambda dask_worker: sum(1 for entry in dask_worker.state.log
                                                 if "worker_task" in str(entry[0])))
    assert len(ran) == 2 and all(count > 0 for count in ran.values()), ran

    # the store reproduces on the cluster, whole and spot-checked, and says where its cells ran again
    for words in ((), ("--cells", "5", "--seed", "1")):
        again = subprocess.run([sys.executable, "-m", "faultslip.cli", "reproduce", str(remote), "--scheduler", address,
                                "--json", *words], capture_output=True, text=True, timeout=300)
        assert again.returncode == 0, again.stderr
        report = json.loads(again.stdout)
        assert report["matches"] and report["checksum"] == "matches", report
        assert report["executor"].startswith(f"dask cluster at {address}"), report["executor"]

    # the store converts to the netCDF file a netCDF sweep writes, and that file reproduces
    converted = tmp_path / "converted.nc"
    result = subprocess.run([sys.executable, "-m", "faultslip.cli", "convert", str(remote), "-o", str(converted),
                             "--json"], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    direct = tmp_path / "direct.nc"
    _sweep(str(study), "-o", str(direct), "--chunks", "500")
    with xr.open_dataset(converted, decode_cf=False) as a, xr.open_dataset(direct, decode_cf=False) as b:
        from faultslip.studies.streaming import compare_datasets

        comparison = compare_datasets(a, b)
        assert max(comparison["differences"].values()) == 0.0
        assert not (comparison["missing"] or comparison["extra"] or comparison["attribute_differences"])


def test_a_2d_fault_study_on_a_real_cluster_equals_one_process(cluster, tmp_path):
    """Each cell of a 2-D fault study is a whole run; on the cluster's workers it gives the same bits."""
    address, _ = cluster
    configs = Path(__file__).resolve().parents[3] / "configs"
    study = tmp_path / "study2d.toml"
    study.write_text(f'[study]\nbase = "{configs / "fault_2d_small.toml"}"\n[sweep]\n'
                     'critical_slip = ["24 mm", "30 mm"]\n')
    local, remote = tmp_path / "local2d.zarr", tmp_path / "remote2d.zarr"
    _sweep(str(study), "-o", str(local), "--workers", "1")
    summary = _sweep(str(study), "-o", str(remote), "--scheduler", address)
    assert summary["executor"] == f"dask cluster at {address}" and summary["cells"] == 2
    with _raw(local) as a, _raw(remote) as b:
        for name in a.data_vars:
            assert a[name].values.tobytes() == b[name].values.tobytes(), name
