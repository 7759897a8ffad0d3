"""Running a study chunk by chunk: streamed to disk, resumable, local or on a dask cluster.

The grid is cut into blocks of about ``chunk_cells`` cells (whole trailing dimensions first).
Blocks are computed independently (:func:`faultslip.studies.grid.compute_block`, pure) by the chosen
executor: in this process, a local process pool, a dask ``LocalCluster`` (``scheduler="local"``)
or an existing dask.distributed cluster (``scheduler=ADDRESS``). At most two blocks per worker
are in flight, so memory stays flat however large the grid; each finished block is written into
``OUT.nc.partial`` (netCDF4, zlib) and recorded in ``OUT.nc.progress.json``. When every block is
written the partial file is renamed over ``OUT.nc`` in one step: an interrupted run leaves the
previous ``OUT.nc`` (or nothing) under the final name, and ``resume=True`` continues from the
partial file if it belongs to the same study.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import re
import shutil
import sys
import contextlib
import tempfile
import time
import warnings
from concurrent.futures import BrokenExecutor
from pathlib import Path

import numpy as np

from faultslip.io.progress import reporter
from faultslip.io import budget, gate
from faultslip.io.atomic import commit, working_copy, write_text_atomic
from faultslip.io.chunks import DIRECT_COMPRESSIONS, ChunkFile, block_digest, encode_chunk, padded
from faultslip.io.netcdf import (CHECKSUM_ATTRIBUTE, COVERS_ATTRIBUTE, chunk_map, create_chunked, file_layout_checksum,
                                 layout_checksum, open_for_append, seal)
from faultslip.io.zarr_store import (CHECKSUM as STORE_CHECKSUM, DIGESTS, check_block_digests, check_store_checksum,
                                      create_store, finish_store, is_store, remove_store,
                                      layout_checksum as store_layout_checksum, require_store,
                                      require_zarr, set_block_digests, store_metadata, update_block_digests,
                                      write_region)
from faultslip.errors import FaultslipError, InputError
from faultslip.io.outputs import check_output, disk_is_full, full_disk_error, output_lock, refuse_links
from faultslip.io.processes import (THREADS_VARIABLE, SharedRing, descendants, reap, run_windowed, shared_segment,
                                    stop_pool, worker_pool)
from faultslip.io.resources import open_dataset_lazily, probe_netcdf, stored_block_digests
from faultslip.contract.cells import collect_cell_failures
from faultslip.studies.grid import block_arrays, compute_block, finish, load_study, parse_study, template_block

DEFAULT_CHUNK_CELLS = 2**19
#: netCDF4 compression filters: zlib is readable everywhere (default); zstd is ~2.5x faster to write
#: and needs netCDF-C >= 4.9 with its plugins to read; none writes fastest and largest.
COMPRESSIONS = ("zlib", "zstd", "none")
FORMATS = ("netcdf", "zarr")
FLOAT_FILL = np.nan
INT_FILL = np.int8(-127)


def stored(dtype) -> tuple:
    """How an output is stored: (numpy type, fill value); flags as int8, everything else as float64."""
    return (np.int8, INT_FILL) if np.issubdtype(dtype, np.integer) else (np.float64, FLOAT_FILL)


#: The key under which a block's task returns its digest beside its chunks (no output is named "").
DIGEST = ""


#: A block's target wall time: long enough to amortise its dispatch and write, short enough that slow
#: cells (simulated, or rate-and-state cycles) spread over every worker.
BLOCK_SECONDS = 2.0


def default_chunk_cells(study) -> int:
    """Cells per block when none is given: about :data:`BLOCK_SECONDS` of work, at most 2**19 cells."""
    return int(min(DEFAULT_CHUNK_CELLS, max(1, BLOCK_SECONDS / study.seconds_per_cell())))


def plan_blocks(study, chunk_cells: int = DEFAULT_CHUNK_CELLS):
    """Chunk size per dimension and the list of blocks (name -> slice), trailing dimensions whole first."""
    if chunk_cells < 1:
        raise InputError(f"--chunks must be a positive number of cells, got {chunk_cells}")
    names = list(study.dims)
    sizes = [len(study.dims[n]) for n in names]
    chunks = [1] * len(names)
    product = 1
    for index in range(len(names) - 1, -1, -1):
        if product * sizes[index] <= chunk_cells:
            chunks[index] = sizes[index]
            product *= sizes[index]
        else:
            chunks[index] = max(1, chunk_cells // product)
            break
    ranges = [range(0, size, chunk) for size, chunk in zip(sizes, chunks)]
    blocks = [{n: slice(start, min(start + c, size)) for n, start, c, size in zip(names, starts, chunks, sizes)}
              for starts in itertools.product(*ranges)]
    return dict(zip(names, chunks)), blocks


#: A dask scheduler's address: "local", or [protocol://]host:port.
_ADDRESS = re.compile(r"^(?:(?:tcp|tls|inproc|ucx|ws|wss)://)?[A-Za-z0-9_.\-\[\]:]*[A-Za-z0-9_.\-\]]:\d{1,5}$")


def check_scheduler(scheduler) -> None:
    """Refuse, before any work, a ``--scheduler`` that is neither ``local``, ``slurm`` nor an address with a
    port."""
    if scheduler is None or scheduler in ("local", "slurm"):
        return
    if not isinstance(scheduler, str) or not _ADDRESS.match(scheduler.strip()):
        raise InputError(f"--scheduler must be 'local', 'slurm' or a dask scheduler's address with its port, e.g. "
                         f"'tcp://10.0.0.5:8786', got {scheduler!r}")


#: A SLURM worker job's resources where dask's jobqueue configuration sets none (jobqueue.slurm in
#: ~/.config/dask/jobqueue.yaml: queue, account, cores, memory, walltime, job_extra_directives, ...).
SLURM_DEFAULTS = {"cores": 1, "processes": 1, "memory": "2GiB", "walltime": "24:00:00"}


def _slurm_cluster(workers: int):
    """A dask-jobqueue SLURMCluster of ``workers`` one-worker jobs, kept at that size (a job that is cancelled or
    killed is replaced by a new one; the tasks it held are computed again elsewhere)."""
    try:
        import dask  # heavy: imported where used
        from dask_jobqueue import SLURMCluster  # heavy: optional (faultslip[dask]), imported where used
    except ImportError:
        raise InputError("--scheduler slurm needs dask-jobqueue: pip install 'faultslip[dask]'") from None
    if shutil.which("sbatch") is None:
        raise InputError("--scheduler slurm submits worker jobs with sbatch, which is not on this machine's PATH")
    configured = dask.config.get("jobqueue.slurm", default={}) or {}
    settings = {key: value for key, value in SLURM_DEFAULTS.items() if configured.get(key) is None}
    # the jobs' logs go where dask's configuration says, else to a temporary folder: not slurm-N.out files in
    # the folder the study was started from
    logs = configured.get("log-directory") or tempfile.mkdtemp(prefix="faultslip-slurm-logs-")
    cluster = SLURMCluster(job_name="faultslip", python=sys.executable,
                           local_directory=configured.get("local-directory") or tempfile.gettempdir(),
                           log_directory=logs, scheduler_options={"dashboard_address": ":0"}, **settings)
    cluster.adapt(minimum=workers, maximum=workers)
    return cluster


def _executor(scheduler, workers, study):
    """(submit, wait_any, shutdown, label) for the chosen executor. A local pool's workers fork from this process
    after it has imported what the study's cells import (``Study.imports``): imported once and shared, not once in
    every worker (a nanoscale sweep on 2 workers imported scipy's integrators twice, which its estimate counts
    once)."""
    if scheduler is None:
        if workers <= 1:
            return None, "in-process"
        budget.import_modules(study.imports())
        return worker_pool(workers), f"process pool ({workers} workers)"
    try:
        from distributed import Client, LocalCluster  # heavy: imported where used
    except ImportError:
        raise InputError("--scheduler needs dask.distributed: pip install 'faultslip[dask]'") from None
    if scheduler == "slurm":
        cluster = _slurm_cluster(workers)
        return Client(cluster), f"SLURM through dask-jobqueue ({workers} worker jobs)"
    if scheduler == "local":
        before = {process.pid for process in descendants()}
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
        # its nannies and workers, to be reaped when it closes (not the process's other children)
        cluster.faultslip_processes = [process for process in descendants() if process.pid not in before]
        # only when asked: on one machine the process pool does the same work faster (docs/studies.md)
        return Client(cluster), f"dask LocalCluster ({workers} workers; without --scheduler the process pool is faster here)"
    try:
        return Client(scheduler, timeout="10s"), f"dask cluster at {scheduler}"
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot reach the dask scheduler at {scheduler!r}: {exc}") from None


def file_layout(study, template):
    """``(dims, coords, variables, attrs)`` of a study's output, for :func:`faultslip.io.netcdf.create_chunked`.

    ``template`` is the study computed on one cell: it gives each output's type and attributes.
    """
    dims = {name: len(values) for name, values in study.dims.items()}
    coords = {}
    for name, values in study.dims.items():
        parameter = study.parameters[name]
        data = np.array(values, dtype=object) if parameter.is_category else np.asarray(values, dtype=float)
        coords[name] = (data, parameter.attrs())
    variables = {}
    for name, array in template.data_vars.items():
        kind, fill = stored(array.dtype)
        variables[name] = (tuple(dims), np.dtype(kind).str[1:], fill, dict(array.attrs))
    return dims, coords, variables, dict(finish(template.copy(), study).attrs)


def _create(path, study, template, chunks, compression="zlib"):
    """An empty netCDF4 file with the study's dimensions, coordinates, variables and attributes."""
    return create_chunked(path, *file_layout(study, template), chunks=chunks, compression=compression)


def _no_chunk_cache(variable):
    """Each block is written once, as whole chunks: HDF5's chunk cache would only hold memory.

    By default it keeps up to tens of MiB of chunks per variable, so memory would grow with the
    run until the caches filled; with a tiny cache every chunk is compressed and written at once.
    """
    variable.set_var_chunk_cache(size=1 << 20, nelems=1, preemption=1.0)


def _write_block(nc, study, block, dataset):
    names = list(study.dims)
    index = tuple(block[n] for n in names)
    for name in dataset.data_vars:
        values = dataset[name].transpose(*names).values if names else dataset[name].values
        nc[name][index] = values


def encode_block(study, block, chunks, compression="zlib") -> dict:
    """Worker task: compute one block and encode each output as the chunk HDF5 stores.

    The block is one chunk of the file (:func:`plan_blocks`), so its bytes go to disk as they
    are; the compression runs here, in the worker, in parallel with the other workers.
    """
    shape = tuple(chunks[n] for n in study.dims)
    encoded = {}
    arrays = block_arrays(study, block)
    for name, values in arrays.items():
        kind, fill = stored(values.dtype)
        encoded[name] = encode_chunk(padded(values.astype(kind, copy=False), shape, fill), compression)
    encoded[DIGEST] = block_digest(arrays)
    return encoded


def encode_block_shared(study, block, chunks, compression, segment: str) -> dict:
    """Pool worker task: :func:`encode_block`, its chunks written into the shared-memory ``segment``
    (:class:`faultslip.io.processes.SharedRing`); returns name -> (offset, length) there, or the bytes of
    a chunk that did not fit."""
    view = shared_segment(segment)
    layout, offset = {}, 0
    for name, data in encode_block(study, block, chunks, compression).items():
        if name == DIGEST:
            layout[name] = data
        elif offset + len(data) <= len(view):
            view[offset:offset + len(data)] = data
            layout[name] = (offset, len(data))
            offset += len(data)
        else:
            layout[name] = data
    return layout


class _ChunkWriter:
    """The parent's side of parallel compression: encoded chunks from the workers go to disk as bytes,
    handed over in shared memory by a local process pool (:meth:`share`), else as the task's result."""

    def __init__(self, path, study, chunks, template, compression):
        self.task = encode_block
        self.extra = (chunks, compression)
        self._dims = list(study.dims)
        self._file = ChunkFile(path, list(template.data_vars), compression)
        self._ring = None
        # the largest encoded block: every output's whole chunk, deflate's worst case (+0.1 % and 64 kB)
        self._block_bytes = sum(math.prod(chunks.values()) * np.dtype(stored(output.dtype)[0]).itemsize
                                for output in template.data_vars.values())

    def share(self, tasks_in_flight: int):
        """Take results from a local process pool through ``tasks_in_flight`` shared-memory segments."""
        self._ring = SharedRing(tasks_in_flight, self._block_bytes * 1.001 + 65536)
        self.task = encode_block_shared

    def lease(self) -> tuple:
        """The extra argument of the next task: a free segment (none without :meth:`share`)."""
        return (self._ring.lease(),) if self._ring is not None else ()

    def release(self, lease=()):
        """Give back the segment of a task that failed."""
        if lease:
            self._ring.release(lease[0])

    def store(self, block, encoded, lease=()):
        offset = tuple(block[n].start for n in self._dims)
        view = self._ring.view(lease[0]) if lease else None
        try:
            for name, data in encoded.items():
                if name == DIGEST:
                    continue
                if isinstance(data, tuple):
                    start, length = data
                    data = view[start:start + length]
                self._file.write(name, offset, data)
        finally:
            if lease:
                self._ring.release(lease[0])

    def digest(self, block, encoded) -> str:
        return encoded[DIGEST]

    def sync(self):
        self._file.flush()

    def close(self):
        try:
            self._file.close()
        finally:
            if self._ring is not None:
                self._ring.close()


class _NetcdfWriter:
    """netCDF4 compresses in this process (zstd, or a study without dimensions, has no direct path)."""

    def __init__(self, nc, study):
        self.task = compute_block
        self.extra = ()
        self._nc, self._study = nc, study

    def lease(self) -> tuple:
        return ()

    def release(self, lease=()):
        pass

    def store(self, block, dataset, lease=()):
        _write_block(self._nc, self._study, block, dataset)

    def digest(self, block, dataset) -> str:
        names = list(self._study.dims)
        return block_digest({name: dataset[name].transpose(*names).values if names else dataset[name].values
                             for name in dataset.data_vars})

    def sync(self):
        self._nc.sync()

    def close(self):
        self._nc.close()


def write_zarr_block(study, block, path) -> int:
    """Worker task: compute one block and write it into its region of the Zarr store at ``path``.

    Nothing but the block's digest (:func:`block_digest`) returns to the client: on a cluster every worker writes its own
    chunks (the store must be on a file system the workers share).
    """
    dataset = compute_block(study, block)
    write_region(path, dataset, dict(block))
    names = list(study.dims)
    return block_digest({name: dataset[name].transpose(*names).values if names else dataset[name].values
                         for name in dataset.data_vars})


class _ZarrWriter:
    """The client's side of a Zarr run: it lays the store out; the workers write the chunks."""

    def __init__(self, path, study, template, chunks, compression, fresh: bool):
        self.task = write_zarr_block
        self.extra = (str(Path(path).resolve()),)
        if fresh:
            create_store(path, *file_layout(study, template), chunks=chunks, compression=compression)
        elif not is_store(path):
            raise InputError(f"{Path(path).name} is not a Zarr store")
        self.layout = store_layout_checksum(path)

    def lease(self) -> tuple:
        return ()

    def release(self, lease=()):
        pass

    def store(self, block, written, lease=()):
        pass

    def digest(self, block, written) -> str:
        return written

    def sync(self):
        pass

    def close(self):
        pass


def _open_writer(partial, study, template, chunks, compression, fresh: bool, file_format: str = "netcdf"):
    """The writer of ``partial``: created (``fresh``) or reopened to resume. Its ``layout`` is the checksum of
    the file's layout as it finds it (:func:`faultslip.io.netcdf.layout_checksum`), which a resume compares with
    the one recorded when the file was created."""
    if file_format == "zarr":
        return _ZarrWriter(partial, study, template, chunks, compression, fresh)
    direct = compression in DIRECT_COMPRESSIONS and bool(study.dims)
    if not fresh:  # HDF5's own structures readable (netCDF4's walk of the layout does not visit them all)
        chunk_map(partial)
    if direct and not fresh:  # the chunks are written through h5py: netCDF4 only reads the layout
        layout = file_layout_checksum(partial)  # before h5py opens it to write
        writer = _ChunkWriter(partial, study, chunks, template, compression)
        writer.layout = layout
        return writer
    if fresh:
        try:
            nc = _create(partial, study, template, chunks, compression)
        except OSError as exc:
            raise InputError(f"cannot write {partial.name}: {exc.strerror or exc}") from None
    else:
        nc = open_for_append(partial)
    try:
        layout = layout_checksum(nc)
        if direct:
            nc.close()
            writer = _ChunkWriter(partial, study, chunks, template, compression)
        else:
            for name in template.data_vars:
                _no_chunk_cache(nc[name])
            writer = _NetcdfWriter(nc, study)
    except BaseException:
        if nc.isopen():
            nc.close()
        raise
    writer.layout = layout
    return writer


def output_format(output, file_format: str | None = None) -> str:
    """``"netcdf"`` or ``"zarr"``: as given, else from the output's suffix (.zarr is Zarr, anything else netCDF)."""
    suffix = Path(str(output)).suffix.lower()
    if file_format is None:
        return "zarr" if suffix == ".zarr" else "netcdf"
    if file_format not in FORMATS:
        raise InputError(f"--format must be one of {', '.join(FORMATS)}, got {file_format!r}")
    return file_format


def check_study_output(output, file_format: str, inputs=(), overwrite: bool = False) -> Path:
    """The checks of :func:`faultslip.io.outputs.check_output`, for a netCDF file or a Zarr store."""
    if file_format == "zarr":
        require_zarr()
        return check_output(output, label="-o", suffixes=(".zarr",), inputs=inputs, overwrite=overwrite,
                            store=True)
    return check_output(output, label="-o", suffixes=(".nc",), inputs=inputs, overwrite=overwrite)


def run_study(study, output, *, chunk_cells: int | None = None, scheduler: str | None = None, workers: int = 2,
              resume: bool = False, progress=None, compression: str = "zlib", overwrite: bool = True,
              inputs=(), file_format: str | None = None) -> dict:
    """Compute ``study`` into ``output`` (netCDF4, or a Zarr store); returns a summary (blocks, cells, seconds, executor).

    The output is checked before any work (folder, extension, an input of the run, an existing file
    without ``overwrite``) and locked while it is written: a second run on the same output is refused.
    ``file_format`` is ``"netcdf"`` or ``"zarr"`` (default: from the suffix, .nc or .zarr).
    ``progress``: True for a bar, or a callable (done, total) over blocks (:mod:`faultslip.io.progress`).
    """
    progress = reporter(progress, "sweep", "chunk")
    if compression not in COMPRESSIONS:
        raise InputError(f"compression must be one of {', '.join(COMPRESSIONS)}, got {compression!r}")
    check_scheduler(scheduler)
    file_format = output_format(output, file_format)
    output = check_study_output(output, file_format, inputs, overwrite)
    with output_lock(output, "faultslip sweep", overwrite=overwrite):
        try:
            try:
                return _run_locked(study, output, chunk_cells, scheduler, workers, resume, progress, compression,
                                   file_format)
            except _ResumedFileDamaged as damaged:  # seen only once the file was written to: start over, once
                warnings.warn(f"{output.name}.partial was damaged where the resume's checks could not see it "
                              f"(its values and layout matched their records, but the file failed once written to: "
                              f"{type(damaged.cause).__name__}: {damaged.cause}); computing the study from the start",
                              stacklevel=2)
                # the start over replaces them anyway: gone first, the run does not also call them an interrupted
                # run's and ask for --resume, which the user passed and this warning answered
                remove_store(output.with_name(output.name + ".partial"))
                output.with_name(output.name + ".progress.json").unlink(missing_ok=True)
                return _run_locked(study, output, chunk_cells, scheduler, workers, False, progress, compression,
                                   file_format)
        except FaultslipError:
            raise
        except Exception as exc:  # zarr and HDF5 fail on a full disk in their own words, anywhere in the run
            if disk_is_full(exc, output.parent):
                remove_store(output.with_name(output.name + ".partial"))
                output.with_name(output.name + ".progress.json").unlink(missing_ok=True)
                raise full_disk_error(output, output.parent) from None
            raise


class _ResumedFileDamaged(Exception):
    """A resumed partial netCDF file whose library failed once written to or sealed (HDF5's own structures
    damaged where no value, attribute or layout check reaches: one flipped bit, found by the fuzzer): the run
    that raises it starts over."""

    def __init__(self, cause: BaseException):
        super().__init__(str(cause))
        self.cause = cause


#: what netCDF4/HDF5 raise on a file whose internal structures are damaged
_DAMAGE_ERRORS = (RuntimeError, KeyError, IndexError, ValueError)


def _file_damage(exc: BaseException, kinds=_DAMAGE_ERRORS) -> bool:
    """Whether ``exc`` is the netCDF library failing on a damaged file, not a worker pool that broke (a
    BrokenExecutor is a RuntimeError too)."""
    return isinstance(exc, kinds) and not isinstance(exc, BrokenExecutor)


def _damaged_output(output: Path, exc: BaseException) -> InputError:
    """The sentence for a finished output that matched its checksum but failed once written to."""
    return InputError(f"{output.name} matches its checksum, but its HDF5 structures failed once written to "
                      f"({type(exc).__name__}: {exc}); it is left as it was: run the study again instead of "
                      "--retry-failed")


def _usable_resume(partial: Path, ledger: Path, fingerprint: str, blocks: int,
                   resume: bool) -> tuple[set, list, dict, str | None]:
    """Blocks already on disk from an interrupted run, the cells of theirs that failed, each block's digest and the
    checksum of the partial file's layout when it was created, or nothing (with a warning saying why). The ledger
    is trusted only where its own checksum matches; its blocks are verified against the partial file afterwards
    (:func:`_verified_blocks`), and the file's layout when it is reopened (:func:`_same_layout`)."""
    nothing = set(), [], {}, None
    if not (partial.exists() or ledger.exists()):
        return nothing
    if not resume:
        warnings.warn(f"an interrupted run left {partial.name}; starting over (pass --resume to continue it)",
                      stacklevel=3)
        return nothing
    try:
        record = gate.read_json(ledger, "progress record")
        done = {int(i) for i in record["done"]}
        failed = list(record.get("failed", []))
        digests = {int(key): str(value) for key, value in record["digests"].items()}
        layout = record.get("layout")
        same = record.get("fingerprint") == fingerprint and record.get("blocks") == blocks
        intact = record.get("checksum") == gate.json_checksum(record)
    except (InputError, ValueError, KeyError, TypeError, AttributeError):
        warnings.warn(f"the progress record {ledger.name} is unreadable; starting over", stacklevel=3)
        return nothing
    if not intact:
        warnings.warn(f"the progress record {ledger.name} does not match its checksum (it was changed after it was "
                      "written); starting over", stacklevel=3)
        return nothing
    if not same:
        warnings.warn(f"{partial.name} belongs to a different study or chunking; starting over", stacklevel=3)
        return nothing
    if not partial.exists() or any(not 0 <= i < blocks for i in done):
        warnings.warn(f"{partial.name} is missing or inconsistent with its record; starting over", stacklevel=3)
        return nothing
    return done, failed, digests, layout


def _same_layout(partial: Path, writer, recorded) -> bool:
    """Whether the reopened partial file's layout (its attributes, units, types, fill values, chunking and
    coordinates) is the one recorded when it was created; if not, the writer is closed and a warning says why."""
    if writer.layout == recorded:
        return True
    writer.close()
    if recorded is None:
        warnings.warn(f"the progress record of {partial.name} holds no checksum of its layout (a faultslip before "
                      "it recorded one), so an edit of its attributes could not be told; starting over", stacklevel=3)
    else:
        warnings.warn(f"the layout of {partial.name} (its attributes, units, types or coordinates) differs from the "
                      "one recorded when it was created: it was edited since; starting over", stacklevel=3)
    return False


def _verified_blocks(partial: Path, file_format: str, study, blocks: list, done: set, digests: dict) -> set:
    """The blocks of ``done`` whose values in the partial file match the digest the ledger recorded when they were
    written (:func:`faultslip.io.chunks.block_digest`); each other block is recomputed, and said so."""
    names = list(study.dims)
    listed = [index for index in sorted(done) if index in digests]
    found = stored_block_digests(partial, [{name: blocks[index][name] for name in names} for index in listed],
                                 names, zarr=file_format == "zarr")
    verified = {index for index, digest in zip(listed, found) if digest == digests[index]}
    changed = len(done) - len(verified)
    if changed:
        warnings.warn(f"{changed} block(s) of {partial.name} cannot be verified against the digests recorded "
                      f"when they were written (changed, or never completed); recomputing them", stacklevel=3)
    return verified


def failure_ledger(output) -> Path:
    """Where a study lists the cells that failed: ``OUT.nc.failed.json`` beside ``OUT.nc``."""
    output = Path(output)
    return output.with_name(output.name + ".failed.json")


def guarded_task(task, *args):
    """Worker task: ``task(*args)`` on one block, each cell that fails kept at its fill values and listed
    (:func:`faultslip.contract.cells.collect_cell_failures`); returns (the task's result, the failures)."""
    with collect_cell_failures() as failed:
        result = task(*args)
    return result, failed


def worker_task(task, *args):
    """:func:`guarded_task` in a worker process (a pool's, a dask worker's, a SLURM job's): its runs take one
    thread each (:data:`faultslip.io.processes.THREADS_VARIABLE`, unless set), because the workers already
    share out the cores, or the job asked for one."""
    os.environ.setdefault(THREADS_VARIABLE, "1")
    return guarded_task(task, *args)


def _cell_values(study, index: dict) -> dict:
    """A cell's swept values (SI, or category names) from its indices."""
    return {name: (value if isinstance(value, str) else float(value))
            for name, value in ((name, study.dims[name][i]) for name, i in index.items())}


def _failure_reason(exc) -> str:
    """One sentence on why a block's task failed: a cell's own error, or its worker dying."""
    if type(exc).__name__ == "KilledWorker":  # distributed's: the task's worker died on every allowed attempt
        return f"its worker died on every attempt (dask KilledWorker): {exc}"
    return f"{type(exc).__name__}: {exc}"


def _run_locked(study, output, chunk_cells, scheduler, workers, resume, progress, compression, file_format):

    chunk_cells = chunk_cells or default_chunk_cells(study)
    chunks, blocks = plan_blocks(study, chunk_cells)
    partial = output.with_name(output.name + ".partial")
    ledger = output.with_name(output.name + ".progress.json")
    # on a fresh run and on resume alike: nothing this run writes through may lead out of its folder
    refuse_links(partial, ledger, output.with_name(output.name + ".cells"), failure_ledger(output), label="sweep")
    fingerprint = study.fingerprint()
    done: set[int] = set()
    failures: list = []
    started = time.perf_counter()
    if study.cells.checkpoints:  # each cell checkpoints its run here: a resumed study continues it
        study.work_dir = output.with_name(output.name + ".cells")
        study.work_dir.mkdir(exist_ok=True)
    template = template_block(study)
    done, failures, digests, layout = _usable_resume(partial, ledger, fingerprint, len(blocks), resume)
    if done:
        try:
            done = _verified_blocks(partial, file_format, study, blocks, done, digests)
        except InputError as exc:  # unreadable: truncated by a kill -9, or not ours
            warnings.warn(f"cannot verify {partial.name} ({exc}); starting over", stacklevel=2)
            done = set()
        # a block recomputed takes its failures with it; a block that failed whole has no digest and is retried
        failures = [cell for cell in failures if cell.get("block") in done]
        digests = {index: digests[index] for index in done}
    writer = None
    if done:
        try:
            writer = _open_writer(partial, study, template, chunks, compression, fresh=False, file_format=file_format)
        except (OSError, IndexError, KeyError, RuntimeError, InputError) as exc:  # truncated by a kill -9, or foreign
            warnings.warn(f"cannot continue {partial.name} ({exc}); starting over", stacklevel=2)
            done, failures, digests = set(), [], {}
        else:
            if not _same_layout(partial, writer, layout):
                done, failures, digests = set(), [], {}
    if not done:
        if study.work_dir is not None:  # a fresh start: no cell continues a run of another study
            shutil.rmtree(study.work_dir, ignore_errors=True)
            study.work_dir.mkdir()
        remove_store(partial)  # a partial netCDF file or Zarr store
        if ledger.exists():
            ledger.unlink()
        try:
            writer = _open_writer(partial, study, template, chunks, compression, fresh=True, file_format=file_format)
        except BaseException as exc:
            _abandon(exc, None, partial, ledger, output)
            raise
    pending = [i for i in range(len(blocks)) if i not in done]
    resumed = bool(done) and file_format != "zarr"  # a netCDF file continued: HDF5 may fail on damage only now
    workers, reason = choose_execution(study, len(pending), workers, scheduler)
    window = max(workers, 1) + 1
    if scheduler is None and workers > 1 and isinstance(writer, _ChunkWriter):
        # a local pool's workers hand their chunks over in shared memory, not through the result pipe; made
        # before the workers fork, so that they share this process's resource tracker
        writer.share(window)
    executor, label = _executor(scheduler, workers, study)
    label = f"{label}{reason}"
    leases = {}

    def tasks():
        for i in pending:
            leases[i] = writer.lease()
            yield i, (writer.task, study, blocks[i], *writer.extra, *leases[i])

    def record_progress():
        record = {"fingerprint": fingerprint, "blocks": len(blocks), "output": output.name, "done": sorted(done),
                  "layout": writer.layout, "failed": failures,
                  "digests": {str(index): digest for index, digest in sorted(digests.items())}}
        record["checksum"] = gate.json_checksum(record)
        write_text_atomic(ledger, json.dumps(record),
                          immediate=True)  # a resume reads it after a kill: it cannot wait for the run's end

    def finished_block(index, result):
        payload, failed = result
        block = blocks[index]
        digests[index] = writer.digest(block, payload)  # before store: a shared segment is released by it
        writer.store(block, payload, leases.pop(index))
        for local, _, reason in failed:
            cell = {name: block[name].start + i for name, i in zip(study.dims, local)}
            failures.append({"index": cell, "values": _cell_values(study, cell), "reason": reason, "block": index})
        done.add(index)
        if progress:
            progress(len(done), len(blocks))

    def failed_block(index, exc):
        if isinstance(exc, OSError):  # the disk, not the cells: the run stops (and --resume continues it)
            raise exc
        writer.release(leases.pop(index, ()))
        reason = _failure_reason(exc)
        block = blocks[index]
        for local in itertools.product(*(range(block[n].stop - block[n].start) for n in study.dims)):
            cell = {name: block[name].start + i for name, i in zip(study.dims, local)}
            failures.append({"index": cell, "values": _cell_values(study, cell), "reason": reason, "block": index})
        done.add(index)  # its region keeps the fill values; the ledger lists its cells for --retry-failed
        if progress:
            progress(len(done), len(blocks))

    record_progress()
    last_saved = time.perf_counter()

    def tick():
        nonlocal last_saved
        if time.perf_counter() - last_saved > 1.0:
            writer.sync()
            record_progress()
            last_saved = time.perf_counter()

    try:
        # blocks in flight: bounds memory whatever the grid size
        run_windowed(executor, guarded_task if executor is None else worker_task, tasks(), finished_block,
                     window=window, on_tick=tick, on_error=failed_block)
    except BaseException as exc:
        _shutdown(executor, interrupted=True)  # first: no worker may keep running, or block the exit
        _abandon(exc, writer, partial, ledger, output)
        record_progress()  # what is on disk is complete block by block: --resume continues from here
        if isinstance(exc, OSError):
            raise InputError(f"writing {partial.name} failed: {exc.strerror or exc}; "
                             "'--resume' continues once the cause is fixed") from None
        if resumed and _file_damage(exc):
            raise _ResumedFileDamaged(exc) from exc
        raise
    if file_format == "zarr":  # each block's digest goes with the store: a conversion checks every block by it
        writer.close()
        _shutdown(executor)
        set_block_digests(partial, {",".join(str(blocks[index][name].start) for name in study.dims): digest
                                    for index, digest in digests.items()})
        finish_store(partial, output)
    else:
        try:
            writer.close()
            _shutdown(executor)
            seal(partial)
        except _DAMAGE_ERRORS as exc:
            if resumed and _file_damage(exc):
                raise _ResumedFileDamaged(exc) from exc
            raise
        commit(partial, output)
    if ledger.exists():
        ledger.unlink()
    listed = _write_failure_ledger(output, study, fingerprint, failures)
    if study.work_dir is not None:
        shutil.rmtree(study.work_dir, ignore_errors=True)
    return {"blocks": len(blocks), "resumed_blocks": len(blocks) - len(pending), "cells": study.size,
            "chunks": chunks, "seconds": time.perf_counter() - started, "executor": label, "output": str(output),
            "failed_cells": len(failures), "failure_ledger": listed}


def _write_failure_ledger(output: Path, study, fingerprint: str, failures: list) -> str | None:
    """Write (or, with no failure, remove) the study's failure ledger; its path or None."""
    path = failure_ledger(output)
    if not failures:
        path.unlink(missing_ok=True)
        return None
    failures = sorted(({key: value for key, value in cell.items() if key != "block"} for cell in failures),
                      key=lambda cell: [cell["index"][n] for n in study.dims])
    record = {"study": study.name, "fingerprint": fingerprint, "output": output.name, "dimensions": list(study.dims),
              "failed_cells": len(failures), "cells": failures}
    record["checksum"] = gate.json_checksum(record)  # --retry-failed trusts only the cells written here
    write_text_atomic(path, json.dumps(record, indent=1) + "\n")
    return str(path)


def retry_failed(study, output, *, scheduler: str | None = None, workers: int = 2, progress=None,
                 file_format: str | None = None) -> dict:
    """Compute again only the cells ``output``'s failure ledger lists (:func:`failure_ledger`) and write them into
    ``output`` (atomically: a copy is written and renamed over it); cells that fail again stay listed.

    Parameters
    ----------
    study : Study
        The study that wrote ``output`` (its fingerprint must match the ledger's).
    output : str or path
        The study's netCDF file or Zarr store.
    scheduler : str, optional
        As :func:`run_study`'s.
    workers : int
        Workers of a pool or cluster.
    progress : bool or callable, optional
        A bar, or a callable (done, total) over the cells.
    file_format : str, optional
        ``netcdf`` or ``zarr`` (default: from the suffix).

    Returns
    -------
    dict
        ``retried``, ``recovered`` and ``still_failed`` cells, the ledger (or None), seconds and the executor.
    """
    progress = reporter(progress, "retry", "cell")
    check_scheduler(scheduler)
    file_format = output_format(output, file_format)
    output = Path(output)
    ledger = failure_ledger(output)
    if not output.exists():
        raise InputError(f"--retry-failed reruns the failed cells of {output.name}, which does not exist: run the "
                         "study first")
    if not ledger.exists():
        raise InputError(f"{output.name} has no failure ledger ({ledger.name}): no cell of it failed, so there is "
                         "nothing to retry")
    record = gate.read_json(ledger, "failure ledger")
    if not isinstance(record, dict) or record.get("checksum") != gate.json_checksum(record):
        # a cell edited out of the ledger would stay unfilled while the retry reported nothing left to do
        raise InputError(f"the failure ledger {ledger.name} does not match the checksum written with it (it was "
                         "changed after it was written, or an older faultslip wrote it): run the study again instead")
    fingerprint = study.fingerprint()
    try:
        cells = [{name: int(cell["index"][name]) for name in study.dims} for cell in record["cells"]]
        if record.get("fingerprint") != fingerprint:
            raise ValueError
        if any(not 0 <= cell[n] < len(study.dims[n]) for cell in cells for n in study.dims):
            raise ValueError
    except (KeyError, TypeError, ValueError, AttributeError):
        raise InputError(f"the failure ledger {ledger.name} does not belong to this study, or is damaged: run the "
                         "study again instead") from None
    started = time.perf_counter()
    with output_lock(output, "faultslip sweep --retry-failed", overwrite=True):
        partial = output.with_name(output.name + ".partial")
        remove_store(partial)
        if file_format == "zarr":
            check_store_checksum(output)  # its metadata as sealed, and
            check_block_digests(output)  # the store is trusted, and its digests renewed, only if it verifies first
        else:
            # and the file only if it matches its checksum
            probe_netcdf(output, "study output")
        working_copy(output, partial)
        blocks = [{name: slice(cell[name], cell[name] + 1) for name in study.dims} for cell in cells]
        workers, reason = choose_execution(study, len(blocks), workers, scheduler)
        executor, label = _executor(scheduler, workers, study)
        try:
            nc = open_for_append(partial) if file_format == "netcdf" else None
        except RuntimeError as exc:
            remove_store(partial)
            raise _damaged_output(output, exc) from None
        still, recovered = [], []

        def stored_cell(index, result):
            dataset, failed = result
            if failed:
                still.append({"index": cells[index], "values": _cell_values(study, cells[index]), "reason": failed[0][2]})
            else:
                if nc is not None:
                    _write_block(nc, study, blocks[index], dataset)
                else:
                    write_region(partial, dataset, dict(blocks[index]))
                recovered.append(index)
            if progress:
                progress(len(still) + len(recovered), len(blocks))

        def failed_cell(index, exc):
            if isinstance(exc, OSError):
                raise exc
            still.append({"index": cells[index], "values": _cell_values(study, cells[index]),
                          "reason": _failure_reason(exc)})

        try:
            run_windowed(executor, guarded_task if executor is None else worker_task,
                         ((i, (compute_block, study, block)) for i, block in enumerate(blocks)), stored_cell,
                         window=max(workers, 1) + 1, on_error=failed_cell)
        except BaseException as exc:
            _shutdown(executor, interrupted=True)
            if nc is not None:
                try:
                    nc.close()
                except RuntimeError:  # the file already failed: what matters is the first error
                    pass
            remove_store(partial)
            if nc is not None and _file_damage(exc, RuntimeError):
                raise _damaged_output(output, exc) from None
            raise
        _shutdown(executor)
        if nc is not None:
            try:
                nc.close()
                seal(partial)
            except RuntimeError as exc:
                remove_store(partial)
                raise _damaged_output(output, exc) from None
            commit(partial, output)
        else:  # the blocks holding the recovered cells get their digests anew, from what was just written
            update_block_digests(partial, [cells[index] for index in recovered])
            finish_store(partial, output)
        listed = _write_failure_ledger(output, study, fingerprint, still)
    return {"retried": len(cells), "recovered": len(recovered), "still_failed": len(still), "failure_ledger": listed,
            "seconds": time.perf_counter() - started, "executor": f"{label}{reason}", "output": str(output)}


def cell_counts(output, file_format: str = "netcdf", tolerance: float | None = None) -> dict:
    """A finished study's cells counted by every flag it has (regime, method, ... by their meanings), and its
    largest declared error, of any family (the flags are the family's declared outputs).

    Read back chunk by chunk (dask), so memory stays flat however large the output.
    """
    counts = {}
    with open_dataset_lazily(output, "study output", zarr=file_format == "zarr", checked=True) as dataset:
        for name, variable in dataset.data_vars.items():
            meanings = str(variable.attrs.get("flag_meanings", "")).split()
            values = np.atleast_1d(variable.attrs.get("flag_values", []))
            if meanings and len(meanings) == len(values):
                counts[name] = {meaning: int((variable == code).sum()) for meaning, code in zip(meanings, values)}
        if "estimated_relative_error" in dataset:
            error = dataset["estimated_relative_error"]
            unbounded = int(np.isinf(error).sum())  # a model error outside its calibration: not known
            bounded = float(error.where(np.isfinite(error)).max())
            counts["largest_estimated_relative_error"] = None if unbounded else bounded  # JSON has no inf
            if unbounded:
                counts["unbounded_error_cells"] = unbounded
                counts["largest_bounded_estimated_relative_error"] = bounded
            if tolerance is not None:
                counts["above_tolerance"] = int((error > tolerance).sum())
    return counts


#: A process pool pays for itself from about this much single-process work (seconds): starting
#: the workers and shipping the study costs tens of ms (measured in benchmarks/sweep_scale.py).
POOL_WORTH_SECONDS = 0.25


def choose_execution(study, pending_blocks: int, workers: int, scheduler=None) -> tuple[int, str]:
    """``(workers, note)``: the executor this study needs; 1 runs in this process.

    A named dask scheduler is always used as asked. Otherwise a small grid (one block, or less
    work than :data:`POOL_WORTH_SECONDS` by the budget's rate) runs in this process, where a
    pool would only add its start-up time; a large one runs on ``workers`` processes.
    """
    if scheduler is not None:
        return workers, ""
    if workers <= 1:
        return 1, ""
    if pending_blocks <= 1:
        return 1, " (one block: a pool would only add start-up time)"
    seconds = budget.study_estimate(study, None, 1, DEFAULT_CHUNK_CELLS).seconds
    if seconds < POOL_WORTH_SECONDS:
        return 1, f" (about {seconds * 1e3:.0f} ms of work: a pool would cost more than it saves)"
    return workers, ""


def sweep_estimate(study, output=None, workers: int = 1, chunks: int | None = None, scheduler: str | None = None,
                   compression: str = "zlib") -> budget.Estimate:
    """What a sweep would need, before any cell runs (``faultslip sweep STUDY -o OUT --estimate``;
    ``faultslip.hazard.sweep_estimate``): each cell's cost from its family's cost model, on the workers the sweep
    would use, its memory and disk, and the CPU of what it imports (measured, :func:`faultslip.io.budget.with_imports`).

    Parameters
    ----------
    study : str, path or Study
        A study file (a bare name may be a bundled study), or :func:`faultslip.studies.grid.load_study`'s study.
    output : path, optional
        Where its netCDF would go (its disk is counted; nothing is written or checked).
    workers : int
        Worker processes asked for (a small study runs in this process whatever is asked, as the sweep would).
    chunks : int, optional
        Cells per block (default: about a few seconds of work each).
    scheduler : str, optional
        A dask scheduler's address, or ``"slurm"``: then ``workers`` are used as asked.
    compression : str
        The netCDF compression ("zlib", or "none").

    Returns
    -------
    faultslip.io.budget.Estimate
        CPU seconds (on its workers together, and over them), memory and disk.
    """
    if isinstance(study, (str, os.PathLike)):
        study = load_study(study)
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"workers must be a whole number of at least 1, got {workers!r}")
    if chunks is not None and (isinstance(chunks, bool) or not isinstance(chunks, int) or not 1 <= chunks <= 10**9):
        raise InputError(f"chunks must be a number of cells from 1 to 1e9, got {chunks!r}")
    chunk_cells = chunks or default_chunk_cells(study)
    working = choose_execution(study, -(-study.size // chunk_cells), workers, scheduler)[0]
    return budget.with_imports(budget.study_estimate(study, output, working, chunk_cells, compression,
                                                     streamed=True))


def _abandon(exc, writer, partial: Path, ledger: Path, output: Path) -> None:
    """Close an interrupted run's writer. On a full disk the partial output may be inconsistent (HDF5 stops
    mid-write): it and its progress record are removed and the full disk is one sentence."""
    with gate.quiet():  # h5py reports its objects' failed clean-up on stderr: no news to the user
        if writer is not None:
            for step in (writer.sync, writer.close):
                try:
                    step()
                except Exception:  # noqa: BLE001  a writer that failed may fail to close: the disk decides
                    if not disk_is_full(exc, output.parent):
                        raise
    if disk_is_full(exc, output.parent):
        remove_store(partial)
        ledger.unlink(missing_ok=True)
        raise full_disk_error(output, output.parent) from None


def _shutdown(executor, interrupted: bool = False):
    if executor is None:
        return
    if hasattr(executor, "gather"):  # a dask Client (and its LocalCluster, if it made one)
        cluster = getattr(executor, "cluster", None)
        started = getattr(cluster, "faultslip_processes", [])
        executor.close()
        if cluster is not None:
            cluster.close()
            reap(started)  # the cluster's worker processes, gone before the sweep returns
    else:
        stop_pool(executor, interrupted=interrupted)


def _largest_difference(a, b):
    """Relative difference per element; equal values (also inf and NaN pairs) differ by 0."""
    a, b = np.asarray(a), np.asarray(b)
    if not np.issubdtype(a.dtype, np.floating):
        return (a != b).astype(float)
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    with np.errstate(invalid="ignore", over="ignore"):
        scale = np.maximum(np.abs(a), np.abs(b))
        return np.where(same, 0.0, np.abs(a - b) / np.where(scale > 0, scale, 1.0))


#: Global attributes that describe the run, not its results: not compared by :func:`reproduce`.
# of the run, or of how it is stored (a Zarr store's block digests, a netCDF file's checksum)
RUN_ATTRIBUTES = ("history", "source", DIGESTS, CHECKSUM_ATTRIBUTE, COVERS_ATTRIBUTE)


def reproduce(path, output=None, *, chunk_cells=None, workers: int = 2, overwrite: bool = False,
              allow_large: bool = False, cells: int | None = None, seed: int | None = None,
              scheduler: str | None = None) -> dict:
    """Re-run the study embedded in ``path`` and compare everything that carries results.

    Every data variable, coordinate, variable attribute and global attribute (but the run's
    ``history`` and ``source``) is compared. A variable, coordinate or attribute that is missing or
    extra is a mismatch, and so is any value that differs by more than 1e-12 relative, and so is a
    file that does not match the checksum written with it (``checksum``: ``"matches"``,
    ``"differs"``, ``"damaged"``, or ``"absent"`` for a file of a faultslip before checksums). The
    file checked is never written: ``output`` must be another file.

    ``path`` may be a Zarr store (a cluster's sweep): its sealed metadata and its blocks' digests are what its
    checksum is, and the study runs again into a Zarr store (``output``, if given, ends in ``.zarr``).
    ``scheduler`` is :func:`run_study`'s: the cells run again where a sweep's would (a dask cluster, SLURM), and
    the result names the executor.

    ``cells``: a spot check of a study too costly to run again whole. Only that many cells, drawn at random
    (``seed``; None draws one, and the result names it so that the same cells can be checked again), are run
    again, each as a sweep runs it, and compared with the file's: their values, coordinates and variable
    attributes. The file's global attributes and its other cells are then vouched for by its checksum alone.
    """
    check_scheduler(scheduler)
    path = Path(path)
    if not path.exists():
        raise InputError(f"file {str(path)!r} does not exist")
    zarr = path.is_dir()
    if zarr:
        require_zarr()
        path = require_store(path)  # a folder that is not a store: one sentence, before its tree is walked
    if cells is not None and output is not None:
        raise InputError("-o keeps a whole reproduced file, and --cells reruns only some cells: give one of them")
    if seed is not None and cells is None:
        raise InputError("--seed draws the cells of --cells: give --cells too")
    keep = None
    if output is not None:
        keep = check_output(output, label="-o", suffixes=(".zarr",) if zarr else (".nc",), inputs=[path],
                            overwrite=overwrite)

    # probed first, as every read is (a damaged file must not crash this process); a file changed since it was
    # written is not refused here but reported: that it differs from what was written is this command's answer
    checksum = _store_checksum(path) if zarr else probe_netcdf(path, "file", refuse_changed=False)
    label = "store" if zarr else "file"
    with open_dataset_lazily(path, label, zarr=zarr, checked=True) as original:
        attrs = dict(original.attrs)
    if not isinstance(attrs.get("faultslip_study"), str) or not isinstance(attrs.get("faultslip_base_scene"), str):
        raise InputError(f"{path.name} carries no embedded study (faultslip_study attribute); it was not written by faultslip sweep")
    study = parse_study(attrs["faultslip_study"], source=path.name, base_text=attrs["faultslip_base_scene"])
    title = attrs.get("title")
    if isinstance(title, str) and title.startswith("faultslip study: "):  # an unnamed study took its file's name
        study.name = title.removeprefix("faultslip study: ")
    if cells is not None:
        return _reproduce_sample(path, study, cells, seed, workers, allow_large, checksum, zarr, scheduler)
    # the embedded study is checked like any sweep before it runs again (a damaged file may ask for much)
    budget.check(budget.study_estimate(study, keep or path, workers, chunk_cells or default_chunk_cells(study),
                                       streamed=True), allow_large)
    with tempfile.TemporaryDirectory(dir=(keep.parent if keep else None)) as scratch:
        target = keep or Path(scratch) / ("reproduced.zarr" if zarr else "reproduced.nc")
        summary = run_study(study, target, chunk_cells=chunk_cells, scheduler=scheduler, workers=workers,
                            inputs=[path])
        with _comparing(path), open_dataset_lazily(path, label, zarr=zarr, checked=True) as old, \
                open_dataset_lazily(target, "reproduced " + label, zarr=zarr, checked=True) as new:
            comparison = compare_datasets(old, new)
    return {**_judged(comparison, checksum), "cells": summary["cells"], "seconds": summary["seconds"],
            "executor": summary["executor"]}


@contextlib.contextmanager
def _comparing(path: Path):
    """A comparison of ``path`` with its reproduction that fails says so in one sentence."""
    try:
        yield
    except InputError:
        raise
    except Exception as exc:
        raise InputError(f"cannot compare {path.name} with its reproduction: {str(exc)[:200]}") from None


def _judged(comparison: dict, checksum) -> dict:
    """A comparison (:func:`compare_datasets`'s keys) and what the file's checksum check found (``probe_netcdf``'s,
    or :func:`_store_checksum`'s), as :func:`reproduce` reports them: the largest difference, the checksum's verdict
    and whether everything matches."""
    worst = max(comparison["differences"].values()) if comparison["differences"] else 0.0
    verdict = {None: "matches", "mismatch": "differs", "damaged": "damaged", "unsealed": "absent"}[checksum]
    matches = worst <= 1e-12 and not any(comparison[k] for k in ("missing", "extra", "attribute_differences")) \
        and verdict in ("matches", "absent")
    return {"matches": matches, "largest_difference": worst, **comparison, "checksum": verdict}


def _store_checksum(path: Path) -> str | None:
    """A Zarr store's integrity as :func:`faultslip.io.netcdf.probe_netcdf` reports a file's: None where its sealed
    metadata and every block's digest match, ``"mismatch"`` where any does not, ``"unsealed"`` for a store of a
    faultslip before the metadata's checksum."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an unsealed store's warning: reported as "absent" instead
            check_store_checksum(path)
        with gate.decoding(path, "the store", "a Zarr store"):
            check_block_digests(path)
    except InputError:
        return "mismatch"
    return None if STORE_CHECKSUM in store_metadata(path).get(".zattrs", {}) else "unsealed"


def _reproduce_sample(path: Path, study, count, seed, workers: int, allow_large: bool, checksum, zarr: bool,
                      scheduler: str | None) -> dict:
    """:func:`reproduce` on ``count`` cells drawn with ``seed``: each computed as its own block, as a sweep computes
    it (:func:`faultslip.studies.grid.compute_block`), and compared with the file's cell."""
    total = study.size
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 1 <= count <= total:
        raise InputError(f"--cells {count!r}: the study in {path.name} has {total} cells; check 1 to {total} of them")
    if seed is None:
        seed = int(np.random.SeedSequence().generate_state(1)[0])
    elif isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"--seed {seed!r}: a seed is a whole number, 0 or more")
    shape = tuple(len(values) for values in study.dims.values())
    drawn = np.sort(np.random.default_rng(seed).choice(total, size=count, replace=False))
    picked = [dict(zip(study.dims, (int(i) for i in np.unravel_index(flat, shape)))) for flat in drawn]
    estimate = budget.study_estimate(study, None, workers, 1, cells=count)
    budget.check(estimate, allow_large)
    blocks = [{name: slice(cell[name], cell[name] + 1) for name in study.dims} for cell in picked]
    if scheduler is None and (len(blocks) <= 1 or estimate.seconds < POOL_WORTH_SECONDS):
        workers = 1  # a pool would cost more than it saves (a named scheduler is used as asked)
    started = time.perf_counter()
    executor, label = _executor(scheduler, workers, study)
    computed = {}
    try:
        run_windowed(executor, guarded_task if executor is None else worker_task,
                     ((i, (compute_block, study, block)) for i, block in enumerate(blocks)),
                     lambda i, result: computed.__setitem__(i, result[0]), window=max(workers, 1) + 1)
    except BaseException:
        _shutdown(executor, interrupted=True)
        raise
    _shutdown(executor)
    differences, found = {}, {"missing": set(), "extra": set(), "attribute_differences": set()}
    with _comparing(path), open_dataset_lazily(path, "store" if zarr else "file", zarr=zarr, checked=True) as old:
        for i, block in enumerate(blocks):
            # one cell, read whole: compared in memory, not through a dask graph a variable
            cell = compare_datasets(old.isel(block).load(), computed[i], global_attributes=False)
            for name, value in cell["differences"].items():
                differences[name] = max(differences.get(name, 0.0), value)
            for key, names in found.items():
                names.update(cell[key])
    comparison = {"differences": differences, **{key: sorted(names) for key, names in found.items()}}
    return {**_judged(comparison, checksum), "cells": count, "of_cells": total, "sample_seed": seed,
            "sampled": [_cell_values(study, cell) for cell in picked], "sampled_index": picked,
            "seconds": time.perf_counter() - started, "executor": label}


def _same_value(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return False
    if np.issubdtype(a.dtype, np.floating) and np.issubdtype(b.dtype, np.floating):
        return bool(np.all((a == b) | (np.isnan(a) & np.isnan(b))))
    return bool(np.all(a == b))


def compare_datasets(old, new, global_attributes: bool = True) -> dict:
    """What differs between a file and its reproduction: variables, coordinates and attributes (the datasets'
    own too, with ``global_attributes``).

    Returns ``differences`` (name -> largest relative difference), ``missing`` (in the
    reproduction, not in the file), ``extra`` (in the file only) and ``attribute_differences``.
    """
    import xarray as xr  # heavy: imported where used

    differences, attribute_differences = {}, []
    old_names = set(old.data_vars) | set(old.coords)
    new_names = set(new.data_vars) | set(new.coords)
    missing, extra = sorted(new_names - old_names), sorted(old_names - new_names)
    for name in sorted(old_names & new_names):
        a, b = old[name], new[name]
        if a.dims != b.dims or a.shape != b.shape:
            differences[name] = float("inf")
            continue
        if np.issubdtype(a.dtype, np.number) and np.issubdtype(b.dtype, np.number):
            differences[name] = float(xr.apply_ufunc(_largest_difference, a, b, dask="parallelized",
                                                     output_dtypes=[float]).max().compute())
        else:
            differences[name] = 0.0 if _same_value(a.values, b.values) else float("inf")
        for key in sorted(set(a.attrs) | set(b.attrs)):
            if key not in a.attrs or key not in b.attrs or not _same_value(a.attrs[key], b.attrs[key]):
                attribute_differences.append(f"{name}:{key}")
    for key in sorted((set(old.attrs) | set(new.attrs)) - set(RUN_ATTRIBUTES)) if global_attributes else ():
        if key not in old.attrs or key not in new.attrs or not _same_value(old.attrs[key], new.attrs[key]):
            attribute_differences.append(key)
    return {"differences": differences, "missing": missing, "extra": extra,
            "attribute_differences": attribute_differences}
