"""Gridded studies: correctness against the scalar paths, CF files, reproduction, dask, atomicity, resume."""

import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from faultslip.errors import InputError
from faultslip.fault.scaling import Fault
from faultslip.studies.streaming import plan_blocks, reproduce, run_study
from faultslip.studies.grid import parse_study, sweep

YEAR = 365.25 * 86400
STUDY = """
[study]
name = "test study"
base = "san_andreas_1906.toml"

[sweep]
slip_rate = { logspace = ["5 mm/yr", "50 mm/yr", 6] }
zone_width = ["10 km", "13 mi", "30 km"]
lithology = ["granodiorite", "black_marble", "pyrite_dry"]
damping_ratio = [0.0, 0.2]
"""


@pytest.fixture
def study():
    return parse_study(STUDY)


def test_every_cell_matches_the_scalar_fault_estimate(study):
    ds = sweep("san_andreas_1906.toml", slip_rate=["5 mm/yr", "24 mm/yr"], zone_width=["10 km", "13 mi"],
               lithology=["granodiorite", "black_marble", "pyrite_dry"], damping_ratio=[0.0, 0.2])
    for speed in ("5 mm/yr", "24 mm/yr"):
        for width in ("10 km", "13 mi"):
            for lith in ("granodiorite", "black_marble", "pyrite_dry"):
                for zeta in (0.0, 0.2):
                    f = Fault(lithology=lith, zone_width=width, shear_stress="250 bar", slip_rate=speed, damping_ratio=zeta,
                              rupture_length="270 mi", seismogenic_depth="12 km").estimate()
                    cell = ds.isel(slip_rate=0 if speed.startswith("5") else 1, zone_width=0 if width == "10 km" else 1)
                    cell = cell.sel(lithology=lith, damping_ratio=zeta)
                    for key in ("slip_per_event", "recurrence_period", "stress_drop", "moment_magnitude", "static_friction"):
                        assert float(cell[key]) == pytest.approx(getattr(f, key), rel=1e-13), (key, speed, width, lith, zeta)


def test_lab_study_uses_the_exact_cycle_and_finds_steady_sliding():
    from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
    from faultslip.dynamics.spring_slider.slider import SliderSystem

    ds = sweep("lab_glass_dry.toml", loading_rate=["0.01 1/s", "0.1 1/s", "1 1/s"], damping_ratio=[0.0, 0.05])
    assert set(np.unique(ds["method"].values)) == {1}  # exact cycle: the closed form misses 1e-6 here
    assert ds["regime"].sel(damping_ratio=0.05).values.tolist() == [0, 0, 1]  # above theta_c: steady sliding
    assert float(ds["slip_per_event"].sel(damping_ratio=0.05).isel(loading_rate=2)) == 0.0
    exact = exact_cycle(SliderSystem.from_preset("glass_dry", loading_rate="0.1 1/s", damping_ratio=0.05))
    cell = ds.sel(damping_ratio=0.05).isel(loading_rate=1)
    assert float(cell["slip_per_event"]) == pytest.approx(exact.slip_per_event, rel=1e-12)
    assert float(cell["recurrence_period"]) == pytest.approx(exact.period, rel=1e-12)


def test_time_of_stick_base_is_simulated_cell_by_cell():
    ds = sweep("lab_steel_dry_time_of_stick.toml", platform_speed=["2e-5 m/s", "8e-5 m/s"])
    assert set(ds["method"].values.tolist()) == {2}
    amplitudes = ds["slip_per_event"].values
    assert amplitudes[0] > amplitudes[1] > 0  # Cameron: amplitude falls as the speed rises


def test_dask_chunked_sweep_is_lazy_and_identical(study):
    eager = sweep("san_andreas_1906.toml", slip_rate=["5 mm/yr", "50 mm/yr"], zone_width=["10 km", "30 km"])
    lazy = sweep("san_andreas_1906.toml", chunks={"slip_rate": 1}, slip_rate=["5 mm/yr", "50 mm/yr"],
                 zone_width=["10 km", "30 km"])
    assert lazy["slip_per_event"].chunks is not None
    xr.testing.assert_identical(eager.drop_attrs(), lazy.compute().drop_attrs())


def test_cf_netcdf_file_with_units_strings_and_embedded_config(study, tmp_path):
    out = tmp_path / "study.nc"
    summary = run_study(study, out, chunk_cells=20, workers=1)
    assert summary["blocks"] == len(plan_blocks(study, 20)[1]) > 1
    with xr.open_dataset(out) as ds:
        assert ds.attrs["Conventions"] == "CF-1.8" and ds.attrs["source"].startswith("faultslip")
        assert {"title", "history", "faultslip_study", "faultslip_base_scene"} <= set(ds.attrs)
        assert ds.attrs["faultslip_study"] == STUDY
        for name, variable in ds.data_vars.items():
            assert "long_name" in variable.attrs and "units" in variable.attrs, name
        assert ds["slip_rate"].attrs["units"] == "m/s" and ds["zone_width"].attrs["units"] == "m"
        assert ds["lithology"].dtype.kind in "OU" and list(ds["lithology"].values) == ["granodiorite", "black_marble", "pyrite_dry"]
        assert ds["regime"].attrs["flag_meanings"].split()[0] == "stick_slip"
        assert ds["slip_per_event"].encoding["zlib"]
        direct = parse_study(STUDY)
        from faultslip.studies.grid import compute_block
        np.testing.assert_array_equal(ds["slip_per_event"].values, compute_block(direct)["slip_per_event"].values)


def test_reproduce_reruns_the_embedded_config(study, tmp_path, cli):
    out = tmp_path / "study.nc"
    run_study(study, out, chunk_cells=50, workers=1)
    result = reproduce(out, workers=1)
    assert result["matches"] and result["largest_difference"] == 0.0
    cli_result = cli("reproduce", out, "--workers", "1", "--json")
    assert cli_result.code == 0 and cli_result.json["matches"]
    with xr.open_dataset(out) as ds:  # a tampered file no longer reproduces
        tampered = ds.load()
    tampered["slip_per_event"][0, 0, 0, 0] *= 1.01
    tampered.to_netcdf(tmp_path / "tampered.nc")
    assert not reproduce(tmp_path / "tampered.nc", workers=1)["matches"]


def test_local_cluster_result_is_identical_to_serial(study, tmp_path):
    pytest.importorskip("distributed")
    serial, clustered = tmp_path / "serial.nc", tmp_path / "cluster.nc"
    run_study(study, serial, chunk_cells=30, workers=1)
    summary = run_study(study, clustered, chunk_cells=30, scheduler="local", workers=2)
    assert summary["executor"].startswith("dask LocalCluster")
    with xr.open_dataset(serial) as a, xr.open_dataset(clustered) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


def _interrupt_on_call(monkeypatch, number):
    """Make the study's block computation raise KeyboardInterrupt (Ctrl-C) on its ``number``-th call."""
    import faultslip.studies.streaming as study_module  # the names the streaming loop calls

    names = ("compute_block", "block_arrays")  # netCDF4's own writer, and the workers' encoded chunks
    real = {name: getattr(study_module, name) for name in names}
    calls = {"n": 0}

    def flaky(name):
        def call(*args, **kwargs):
            calls["n"] += 1
            if calls["n"] == number:
                raise KeyboardInterrupt
            return real[name](*args, **kwargs)
        return call

    for name in names:
        monkeypatch.setattr(study_module, name, flaky(name))

    def restore():
        for name in names:
            monkeypatch.setattr(study_module, name, real[name])
    return restore


def test_interrupted_sweep_keeps_the_previous_file_and_resumes(study, tmp_path, monkeypatch):
    out = tmp_path / "study.nc"
    previous = parse_study(STUDY.replace('"5 mm/yr"', '"6 mm/yr"'))
    run_study(previous, out, chunk_cells=30, workers=1)
    before = out.read_bytes()
    restore = _interrupt_on_call(monkeypatch, 4)  # the layout's template block comes from grid.template_block
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, chunk_cells=30, workers=1)  # 6 blocks; Ctrl-C while computing the 4th
    assert out.read_bytes() == before  # the final name still holds the complete previous file
    partial, ledger = out.with_name("study.nc.partial"), out.with_name("study.nc.progress.json")
    assert partial.exists() and len(json.loads(ledger.read_text())["done"]) == 3  # 3 blocks, then Ctrl-C
    restore()
    summary = run_study(study, out, chunk_cells=30, workers=1, resume=True)
    assert summary["resumed_blocks"] == 3 and not partial.exists() and not ledger.exists()
    fresh = tmp_path / "fresh.nc"
    run_study(study, fresh, chunk_cells=30, workers=1)
    with xr.open_dataset(out) as a, xr.open_dataset(fresh) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


def test_resume_ignores_a_partial_file_of_another_study(study, tmp_path, monkeypatch):
    out = tmp_path / "s.nc"
    restore = _interrupt_on_call(monkeypatch, 5)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, chunk_cells=30, workers=1)
    restore()
    other = parse_study(STUDY.replace('"30 km"', '"25 km"'))
    with pytest.warns(UserWarning, match="belongs to a different study or chunking; starting over"):
        assert run_study(other, out, chunk_cells=30, workers=1, resume=True)["resumed_blocks"] == 0


def test_a_hard_kill_never_leaves_a_broken_file_under_the_final_name(tmp_path):
    """Killed once its first blocks are on disk. Every cell is integrated (~30 ms a cell, 2,000 cells): a
    closed-form sweep of 1e5 cells could finish, on a fast machine, before the test saw its progress."""
    study_file = tmp_path / "big.toml"
    study_file.write_text('[study]\nbase = "lab_steel_dry_polynomial.toml"\n[sweep]\n'
                          'platform_speed = { logspace = ["1e-5 m/s", "1e-4 m/s", 2000] }\n')
    out = tmp_path / "big.nc"
    process = subprocess.Popen([sys.executable, "-m", "faultslip.cli", "sweep", str(study_file), "-o", str(out),
                                "--chunks", "20", "--workers", "1", "--allow-large"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE)
    ledger = out.with_name("big.nc.progress.json")
    deadline = time.time() + 120
    while time.time() < deadline and process.poll() is None:  # wait until some chunks are on disk
        if ledger.exists() and json.loads(ledger.read_text() or "{}").get("done"):
            break
        time.sleep(0.05)
    assert process.poll() is None, "the sweep finished before it could be interrupted"
    process.send_signal(signal.SIGKILL)
    process.wait()
    assert not out.exists()  # nothing under the final name: no half-written file
    assert out.with_name("big.nc.partial").exists()


@pytest.mark.parametrize("sweep_table, message", [
    ('slip_rat = ["1 mm/yr"]', "unknown parameter 'slip_rat'.*did you mean slip_rate"),
    ("slip_rate = []", "slip_rate in <study> is empty"),
    ('slip_rate = ["2 bar"]', "must be a speed"),
    ('slip_rate = { logspace = ["1 mm/yr", "10 mm/yr", 0] }', "is empty"),
    ('lithology = ["granodiorit"]', "did you mean granodiorite"),
    ('slip_rate = { linspace = ["1 mm/yr", "10 mm/yr"] }', "needs \\[start, stop, count\\]"),
])
def test_bad_studies_are_refused(sweep_table, message):
    with pytest.raises(InputError, match=message):
        parse_study(f'[study]\nbase = "san_andreas_1906.toml"\n[sweep]\n{sweep_table}\n')


def test_bad_study_via_cli_writes_no_file(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\nzone_widht = ["10 km"]\n')
    out = tmp_path / "out.nc"
    result = cli("sweep", bad, "-o", out)
    assert result.code == 2 and "zone_widht" in result.err and "did you mean zone_width" in result.err
    assert "Traceback" not in result.err
    assert list(tmp_path.iterdir()) == [bad]


def test_sweep_cli_json(cli, tmp_path):
    study_file = tmp_path / "s.toml"
    study_file.write_text(STUDY)
    result = cli("sweep", study_file, "-o", tmp_path / "o.nc", "--chunks", "40", "--workers", "1", "--json")
    assert result.code == 0, result.err
    data = result.json
    assert data["cells"] == 6 * 3 * 3 * 2 and data["dimensions"]["lithology"] == 3 and data["blocks"] > 1


# --- moving bytes: shared memory, the heap, and no xarray in a closed-form sweep ------------------------

BIG_STUDY = """[study]
name = "pool handover"
base = "san_andreas_1906.toml"
method = "closed_form"
[sweep]
shear_modulus = { linspace = ["0.15e6 bar", "0.35e6 bar", 6] }
slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 200] }
zone_width = { linspace = ["5 km", "30 km", 300] }
"""


def _shared_segments() -> set:
    from pathlib import Path

    shm = Path("/dev/shm")
    return {p.name for p in shm.iterdir()} if shm.is_dir() else set()


def test_pool_workers_hand_their_chunks_over_in_shared_memory(tmp_path, monkeypatch):
    """A pool's workers write their encoded chunks into shared-memory segments leased per task (not the
    result pipe): the file is the same bits as one process writes, and no segment outlives the run."""
    import faultslip.studies.streaming as streaming
    from faultslip.io.processes import SharedRing

    study = parse_study(BIG_STUDY)
    monkeypatch.setattr(streaming, "choose_execution", lambda study, pending, workers, scheduler=None: (workers, ""))
    leased = []
    real_lease = SharedRing.lease

    def lease(self):
        leased.append(real_lease(self))
        return leased[-1]

    monkeypatch.setattr(SharedRing, "lease", lease)
    summary = run_study(study, tmp_path / "pool.nc", workers=2, chunk_cells=60_000)
    assert summary["blocks"] == 6 and "process pool (2 workers)" in summary["executor"] and len(leased) == 6
    # the ring's own segments are unlinked (only its own: the suite's other processes make and free theirs
    # meanwhile, so /dev/shm as a whole may hold others')
    assert not set(leased) & _shared_segments()
    run_study(study, tmp_path / "one.nc", workers=1, chunk_cells=60_000)
    with xr.open_dataset(tmp_path / "pool.nc") as pool, xr.open_dataset(tmp_path / "one.nc") as one:
        for name in one.data_vars:
            np.testing.assert_array_equal(pool[name].values, one[name].values)


def _probe_module_pid():
    import faultslip_probe_module

    return faultslip_probe_module.PID


def test_a_pools_workers_fork_after_the_cells_imports(tmp_path, monkeypatch):
    """A pool's workers fork after this process has imported what the study's cells import (Study.imports): the
    modules are imported once and shared, where each worker had imported them again (scipy's integrators, twice
    on 2 workers, for a nanoscale sweep whose estimate counts them once). A module that records the process that
    imported it is the parent's in every worker."""
    import multiprocessing
    import os

    from faultslip.studies.streaming import _executor

    if multiprocessing.get_start_method() != "fork":
        pytest.skip("workers that fork share the parent's imports; other start methods import afresh")
    (tmp_path / "faultslip_probe_module.py").write_text("import os\nPID = os.getpid()\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "faultslip_probe_module", raising=False)

    class Cells:
        def imports(self):
            return ("faultslip_probe_module",)

    pool, label = _executor(None, 2, Cells())
    try:
        assert label == "process pool (2 workers)" and "faultslip_probe_module" in sys.modules
        assert {pool.submit(_probe_module_pid).result() for _ in range(4)} == {os.getpid()}
    finally:
        pool.shutdown(wait=True)
        sys.modules.pop("faultslip_probe_module", None)


def test_a_chunk_too_large_for_its_segment_travels_as_bytes():
    from multiprocessing.shared_memory import SharedMemory

    from faultslip.io.chunks import encode_chunk
    from faultslip.studies.streaming import encode_block, encode_block_shared

    study = parse_study(BIG_STUDY)
    chunks, blocks = plan_blocks(study, 60_000)
    expected = encode_block(study, blocks[0], chunks)
    small = SharedMemory(create=True, size=len(expected["slip_per_event"]) + len(expected["recurrence_period"]))
    try:
        layout = encode_block_shared(study, blocks[0], chunks, "zlib", small.name)
        assert list(layout) == list(expected)
        for name, where in layout.items():
            data = bytes(small.buf[where[0]:where[0] + where[1]]) if isinstance(where, tuple) else where
            assert data == expected[name], name
        assert sum(isinstance(where, tuple) for where in layout.values()) >= 2
        assert any(isinstance(where, bytes) for where in layout.values())
        # an uncompressed chunk ends in its Fletcher-32 checksum, which is 0 for zeros
        assert encode_chunk(np.zeros(3), "none") == np.zeros(3).tobytes() + bytes(4)
    finally:
        small.close()
        small.unlink()


def test_the_heap_keeps_freed_blocks_for_the_next():
    """retain_freed_memory (glibc's mallopt, in pool workers and 'faultslip sweep'): arrays freed and made
    again cost no fresh page faults. A 1e7-cell sweep spent 30 % of its CPU in the kernel before."""
    if not sys.platform.startswith("linux"):
        pytest.skip("glibc's mallopt: Linux only (elsewhere retain_freed_memory returns False)")
    code = ("import resource, sys, numpy as np; from faultslip.io.processes import retain_freed_memory\n"
            "if sys.argv[1] == 'retain': assert retain_freed_memory()\n"
            "before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt\n"
            "for _ in range(20):  # a block's 17 outputs of 4 MB, made and freed together\n"
            "    arrays = [np.full(2**19, float(i)) for i in range(17)]; del arrays\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)")
    faults = {how: int(subprocess.run([sys.executable, "-c", code, how], capture_output=True, text=True,
                                      check=True).stdout) for how in ("default", "retain")}
    # measured: 164,629 faults by default (glibc returns the freed heap top and faults it in again, 4 kB a
    # page), 8,724 retained (the first block's)
    assert faults["default"] > 5 * 17 * 1024  # of 20 blocks x 17 x 1024 pages, half fault afresh
    assert faults["retain"] < faults["default"] / 5


def test_a_closed_form_sweep_never_imports_xarray(tmp_path):
    """Its blocks are numpy and its layout (template_block) a StudyLayout: xarray and pandas cost 0.4-0.55 s
    of a sweep's start, a seventh of a 1e7-cell sweep's whole time."""
    study = tmp_path / "s.toml"
    study.write_text(BIG_STUDY, encoding="utf-8")
    code = ("import sys; from faultslip.cli.main import main; "
            f"main(['sweep', {str(study)!r}, '-o', {str(tmp_path / 'o.nc')!r}, '--json']); "
            "print('loaded: ' + ','.join(m for m in ('xarray', 'pandas', 'dask') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip().splitlines()[-1] == "loaded:"


def test_reading_a_study_back_computes_on_local_threads_without_importing_distributed(tmp_path):
    """A finished study is read back (its cells counted by flag) through open_dataset_lazily. dask, asked for any
    scheduler by name or by none, first imports distributed to look for a client: 0.2 s, and up to a second of
    CPU on a busy host, in every sweep that counts its cells. Read back on this process's threads, it is not
    imported, and the numbers are the file's."""
    import netCDF4

    path = tmp_path / "back.nc"
    with netCDF4.Dataset(path, "w") as written:  # not xarray's writer, which imports distributed for its locks
        written.createDimension("x", 10)
        written.createVariable("a", "f8", ("x",))[:] = np.arange(10.0)
    code = ("import sys\n"
            "from faultslip.io.resources import open_dataset_lazily\n"
            f"with open_dataset_lazily({str(path)!r}, 'a study output', checked=True) as data:\n"
            "    total = float(data['a'].sum())\n"
            "print(total, 'distributed' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["45.0", "False"]


def test_a_blocks_arrays_are_its_datasets_variables():
    from faultslip.studies.grid import block_arrays, compute_block

    study = parse_study(BIG_STUDY)
    block = {"shear_modulus": slice(1, 2), "slip_rate": slice(10, 30), "zone_width": slice(0, 300)}
    dataset, arrays = compute_block(study, block), block_arrays(study, block)
    assert list(arrays) == list(dataset.data_vars)
    for name, values in arrays.items():
        expected = dataset[name].transpose(*study.dims).values
        assert values.dtype == expected.dtype and values.shape == expected.shape
        np.testing.assert_array_equal(values, expected)


@pytest.mark.parametrize("executor", [[], ["--workers", "2"], ["--scheduler", "local", "--workers", "2"]],
                         ids=["default", "pool", "dask"])
def test_no_process_of_a_sweep_outlives_it(executor, tmp_path):
    """Issue 43: processes were left in a sweep's process group after it exited. The sweep runs in its own session;
    the moment it has exited, no worker of its process group is left (a dask LocalCluster's worker used to be),
    and its resource tracker, if it has one, is gone moments later."""
    import os
    from pathlib import Path

    import psutil

    configs = Path(__file__).resolve().parents[3] / "configs"
    command = [sys.executable, "-m", "faultslip.cli", "sweep", str(configs / "study_spring_slider.toml"),
               "-o", str(tmp_path / "out.nc"), "--chunks", "2000", "--json", *executor]
    run = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, err = run.communicate(timeout=300)
    assert run.returncode == 0, err.decode()
    def group():
        left = []
        for process in psutil.process_iter(["pid"]):
            try:
                if process.pid != os.getpid() and os.getpgid(process.pid) == run.pid and \
                        process.status() != psutil.STATUS_ZOMBIE:
                    left.append((process.pid, " ".join(process.cmdline())[:100]))
            except (ProcessLookupError, psutil.Error):
                pass
        return left

    left = group()
    # only multiprocessing's resource tracker may still be finishing (an exiting process shows no command line):
    # it exits by itself once its parent has, after cleaning up what the parent left (a few milliseconds)
    assert all("resource_tracker" in command or not command for _, command in left), left
    deadline = time.monotonic() + 10
    while left and time.monotonic() < deadline:
        time.sleep(0.05)
        left = group()
    assert not left, left


# A resume trusts nothing it cannot verify (issue 69): the ledger by its own checksum, each block by the digest
# recorded when it was written, recomputed from the partial file.

def _interrupted(study, out, monkeypatch, blocks_done: int = 3, compression: str = "zlib"):
    restore = _interrupt_on_call(monkeypatch, blocks_done + 1)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, chunk_cells=30, workers=1, compression=compression)
    restore()
    return out.with_name(out.name + ".partial"), out.with_name(out.name + ".progress.json")


def test_a_ledger_edited_to_list_every_block_as_done_is_refused(study, tmp_path, monkeypatch):
    out = tmp_path / "s.nc"
    partial, ledger = _interrupted(study, out, monkeypatch)
    record = json.loads(ledger.read_text())
    record["done"] = list(range(record["blocks"]))
    ledger.write_text(json.dumps(record))
    with pytest.warns(UserWarning, match="does not match its checksum"):
        summary = run_study(study, out, chunk_cells=30, workers=1, resume=True)
    assert summary["resumed_blocks"] == 0
    fresh = tmp_path / "fresh.nc"
    run_study(study, fresh, chunk_cells=30, workers=1)
    with xr.open_dataset(out) as a, xr.open_dataset(fresh) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


def test_a_ledger_resigned_after_its_blocks_were_listed_done_still_recomputes_them(study, tmp_path, monkeypatch):
    """Even with its checksum made to match, a block listed done without a digest of its values is recomputed."""
    from faultslip.io.gate import json_checksum

    out = tmp_path / "s.nc"
    partial, ledger = _interrupted(study, out, monkeypatch)
    record = json.loads(ledger.read_text())
    record["done"] = list(range(record["blocks"]))
    record["checksum"] = json_checksum(record)
    ledger.write_text(json.dumps(record))
    with pytest.warns(UserWarning, match="cannot be verified"):
        summary = run_study(study, out, chunk_cells=30, workers=1, resume=True)
    assert summary["resumed_blocks"] == 3
    with xr.open_dataset(out) as dataset:
        assert not any(bool(dataset[name].isnull().any()) for name in dataset.data_vars
                       if dataset[name].dtype.kind == "f" and name != "estimated_relative_error")


def test_a_value_edited_in_the_partial_file_is_recomputed_not_carried(study, tmp_path, monkeypatch):
    import netCDF4

    out = tmp_path / "s.nc"
    partial, ledger = _interrupted(study, out, monkeypatch)
    with netCDF4.Dataset(partial, "a") as nc:
        name = next(key for key, variable in nc.variables.items()
                    if key not in nc.dimensions and variable.dtype.kind == "f" and variable.ndim)
        variable = nc[name]
        variable[(0,) * variable.ndim] = 1234.5
    with pytest.warns(UserWarning, match="1 block\\(s\\) of s.nc.partial cannot be verified"):
        summary = run_study(study, out, chunk_cells=30, workers=1, resume=True)
    assert summary["resumed_blocks"] == 2
    fresh = tmp_path / "fresh.nc"
    run_study(study, fresh, chunk_cells=30, workers=1)
    with xr.open_dataset(out) as a, xr.open_dataset(fresh) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


#: Edits of a partial file's layout that keep it a valid netCDF file, each undone by a fresh start: what the digests
#: of its blocks cannot see (they cover the values of the blocks written, not the attributes or coordinates).
LAYOUT_EDITS = {
    "a unit": lambda nc: nc["slip_per_event"].setncattr("units", "ft"),
    "a global attribute": lambda nc: nc.setncattr("title", "edited"),
    "a new attribute": lambda nc: nc["recurrence_period"].setncattr("scale_factor", 2.0),
    "a coordinate value": lambda nc: nc["zone_width"].__setitem__(0, 11000.0),
    "a category name": lambda nc: nc["lithology"].__setitem__(1, "gabbro"),
}


@pytest.mark.parametrize("compression", ["zlib", "zstd"])  # chunks written through h5py, and through netCDF4
@pytest.mark.parametrize("edit", sorted(LAYOUT_EDITS))
def test_a_layout_edited_in_the_partial_file_starts_the_run_over(study, tmp_path, monkeypatch, edit, compression):
    import netCDF4

    out = tmp_path / "s.nc"
    partial, _ = _interrupted(study, out, monkeypatch, compression=compression)
    with netCDF4.Dataset(partial, "a") as nc:
        LAYOUT_EDITS[edit](nc)
    with pytest.warns(UserWarning, match="the layout of s.nc.partial .* differs from the one recorded when it was "
                                         "created: it was edited since; starting over"):
        summary = run_study(study, out, chunk_cells=30, workers=1, resume=True, compression=compression)
    assert summary["resumed_blocks"] == 0
    fresh = tmp_path / "fresh.nc"
    run_study(study, fresh, chunk_cells=30, workers=1, compression=compression)
    with xr.open_dataset(out, decode_cf=False) as a, xr.open_dataset(fresh, decode_cf=False) as b:
        xr.testing.assert_identical(a.drop_attrs(deep=False), b.drop_attrs(deep=False))  # units and coordinates too
        assert "title" not in a.attrs or a.attrs["title"] == b.attrs["title"]


@pytest.mark.parametrize("compression", ["zlib", "zstd"])
def test_an_untouched_partial_file_resumes_with_its_layout_unchanged(study, tmp_path, monkeypatch, compression):
    """The layout recorded when the file was created (open to write) is the one read when it is reopened."""
    out = tmp_path / "s.nc"
    _interrupted(study, out, monkeypatch, compression=compression)
    assert run_study(study, out, chunk_cells=30, workers=1, resume=True, compression=compression)["resumed_blocks"] == 3


@pytest.mark.parametrize("where", ["seal", "store"])
def test_a_resumed_file_that_fails_once_written_to_is_computed_from_the_start(study, tmp_path, monkeypatch, where):
    """One flipped bit in HDF5's own structures passed every check of the resume (values, attributes, layout) and
    failed only when the continued file was written or sealed ("Can't open HDF5 attribute", found by the fuzzer):
    the run says so and starts over once, ending on the uninterrupted run's values, not a traceback."""
    import faultslip.studies.streaming as study_module

    out = tmp_path / "s.nc"
    _interrupted(study, out, monkeypatch)
    failed = {"n": 0}

    def damaged(original):
        def call(*args, **kwargs):
            if not failed["n"]:
                failed["n"] += 1
                raise RuntimeError("NetCDF: Can't open HDF5 attribute")
            return original(*args, **kwargs)
        return call

    if where == "seal":
        monkeypatch.setattr(study_module, "seal", damaged(study_module.seal))
    else:
        for writer in (study_module._NetcdfWriter, study_module._ChunkWriter):  # whichever writes this file
            monkeypatch.setattr(writer, "store", damaged(writer.store))
    with pytest.warns(UserWarning, match="damaged where the resume's checks could not see it.*from the start") as said:
        summary = run_study(study, out, chunk_cells=30, workers=1, resume=True)
    assert summary["resumed_blocks"] == 0 and failed["n"] == 1
    # one warning: the start over does not also ask for the --resume that was passed
    assert not [w for w in said if "pass --resume" in str(w.message)]
    assert not out.with_name("s.nc.partial").exists() and not out.with_name("s.nc.progress.json").exists()
    fresh = tmp_path / "fresh.nc"
    run_study(study, fresh, chunk_cells=30, workers=1)
    with xr.open_dataset(out) as a, xr.open_dataset(fresh) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


def test_a_fresh_run_whose_file_fails_is_not_retried(study, tmp_path, monkeypatch):
    # only a resumed file starts over: a fresh one failing has another cause, and it is not hidden
    import faultslip.studies.streaming as study_module

    def broken(*args, **kwargs):
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(study_module, "seal", broken)
    with pytest.raises(RuntimeError, match="HDF error"):
        run_study(study, tmp_path / "s.nc", chunk_cells=30, workers=1)


@pytest.mark.parametrize("where", ["seal", "open_for_append"])
def test_a_retry_on_an_output_that_fails_once_written_to_is_one_sentence_and_keeps_it(study, tmp_path, monkeypatch,
                                                                                     where):
    """--retry-failed trusts an output that matches its checksum; HDF5 damage no checksum sees fails only when its
    working copy is written: one sentence, the output and its ledger as they were, no partial copy left."""
    import faultslip.studies.streaming as study_module

    out = tmp_path / "s.nc"
    run_study(study, out, chunk_cells=30, workers=1)
    first = {name: 0 for name in study.dims}
    study_module._write_failure_ledger(out, study, study.fingerprint(),
                                       [{"index": first, "values": {}, "reason": "a solver failure"}])
    before, ledger = out.read_bytes(), study_module.failure_ledger(out).read_bytes()

    def damaged(*args, **kwargs):
        raise RuntimeError("NetCDF: Can't open HDF5 attribute")

    monkeypatch.setattr(study_module, where, damaged)
    with pytest.raises(InputError, match="matches its checksum, but its HDF5 structures failed.*run the study again"):
        study_module.retry_failed(study, out, workers=1)
    assert out.read_bytes() == before and study_module.failure_ledger(out).read_bytes() == ledger
    assert not out.with_name("s.nc.partial").exists()


def test_a_progress_record_without_a_layout_starts_the_run_over(study, tmp_path, monkeypatch):
    """An interrupted run of a faultslip that recorded no layout: its partial file's attributes cannot be checked."""
    from faultslip.io import gate

    out = tmp_path / "s.nc"
    partial, ledger = _interrupted(study, out, monkeypatch)
    record = json.loads(ledger.read_text())
    del record["layout"]
    record["checksum"] = gate.json_checksum(record)
    ledger.write_text(json.dumps(record))
    with pytest.warns(UserWarning, match="holds no checksum of its layout"):
        assert run_study(study, out, chunk_cells=30, workers=1, resume=True)["resumed_blocks"] == 0


@pytest.mark.parametrize("resume", [False, True])
def test_a_partial_output_planted_as_a_link_is_never_written_through(study, tmp_path, monkeypatch, resume):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    victim = outside / "victim.nc"
    victim.write_bytes(b"keep me")
    folder = tmp_path / "run"
    folder.mkdir()
    out = folder / "s.nc"
    if resume:
        _interrupted(study, out, monkeypatch)
        out.with_name("s.nc.partial").unlink()
    out.with_name("s.nc.partial").symlink_to(victim)
    with pytest.raises(InputError, match="symbolic link, which faultslip never follows"):
        run_study(study, out, chunk_cells=30, workers=1, resume=resume)
    assert victim.read_bytes() == b"keep me" and not out.exists()


def test_an_axis_of_a_hundred_thousand_values_is_checked_without_a_scene_per_value(monkeypatch):
    """Its ends and an even spread are read (64 scenes), not 100,000, before the budget sees the study."""
    from faultslip.contract import cells as cells_module

    built = []
    original = cells_module.checked_values
    monkeypatch.setattr(cells_module, "checked_values", lambda values: built.append(len(values)) or original(values))
    study = parse_study('[study]\nbase = "nanoscale_seed001.toml"\n[sweep]\n'
                        'damping = { linspace = [1.0, 13.0, 100000] }\n')
    assert study.size == 100_000 and built == [100_000]
    picked = original(study.dims["damping"])
    assert len(picked) == 64 and picked[0] == study.dims["damping"][0] and picked[-1] == study.dims["damping"][-1]


def test_an_axis_past_a_million_values_is_refused_before_it_is_built():
    with pytest.raises(InputError, match="at most 1e\\+06"):
        parse_study('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\n'
                    'slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 100000000] }\n')


def test_a_per_cell_condition_flags_only_the_cells_it_is_false_in(tmp_path):
    """Lithology x mu_m over the 1906 scene: mu_m = 0.5 and 0.6 lie above pyrite's mu_so (0.226, water) but below
    granodiorite's (0.65). Only pyrite's cells are flagged; granodiorite's are predicted. A check on some cells
    used to condemn them all."""
    study = parse_study('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\n'
                        'lithology = ["granodiorite", "pyrite_water"]\nmu_m = [0.5, 0.6]\n')
    out = tmp_path / "lith.nc"
    run_study(study, out, workers=1)
    with xr.open_dataset(out) as dataset:
        flagged = dataset["outside_domain"].values
        slip = dataset["slip_per_event"].values
    assert flagged.tolist() == [[0, 0], [1, 1]]
    assert np.all(np.isfinite(slip[0])) and np.all(np.isnan(slip[1]))
    with pytest.raises(InputError, match="in every cell"):
        parse_study('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\nlithology = ["pyrite_water"]\nmu_m = [0.5]\n')
