"""A long run's own files: record streams appended row by row, and the checkpoint that resumes them.

Both live in a run's output folder, where a user (or an attacker) can reach them, so both pass the
door like every other file:

* :class:`RecordStream` appends float64 rows to ``NAME.f8``. It is opened with ``O_NOFOLLOW`` and
  must be a regular file with one link (a planted symbolic or hard link is refused, never written
  through); a fresh run replaces whatever stood at the path without following it. It keeps a
  SHA-256 of every byte written, which the checkpoint records: on resume the file's first rows
  must hash to it, so a flipped bit, a truncation or a foreign file is refused in one sentence,
  never resumed silently.
* :func:`write_checkpoint` saves named arrays as ``.npz`` through :func:`~faultslip.io.atomic.atomic_path`
  (a temporary then a rename; a full disk leaves nothing), with a SHA-256 over every array's
  name, dtype, shape and bytes; :func:`read_checkpoint` reads it through the gate and checks the
  digest and the layout the caller expects, so a truncated, emptied, bit-flipped or re-saved
  checkpoint is one sentence naming the file.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import io
import os
import stat
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.atomic import atomic_path
from faultslip.io.outputs import as_output_error

#: Bytes of rows buffered before they are written: a write per step would cost a system call per step, and a
#: count of rows would hold megabytes of a wide stream (a 2-D fault's profiles are 16 kB a row).
BUFFER_BYTES = 1 << 20
#: Bytes of a finished record read at a time: what a run keeps in memory stays flat in its length.
BLOCK_BYTES = 1 << 20
_FLAGS = getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
_RESUME = "start the run again without --resume"


def _refuse_link(path: Path, exc: OSError) -> InputError:
    if exc.errno == errno.ELOOP or path.is_symlink():
        return InputError(f"{str(path)!r} is a symbolic link, which faultslip never follows; remove it and run again")
    return InputError(f"cannot open {str(path)!r}: {exc.strerror or exc}")


def _check_plain(descriptor: int, path: Path) -> None:
    info = os.fstat(descriptor)
    if not stat.S_ISREG(info.st_mode) or info.st_nlink != 1:
        os.close(descriptor)
        raise InputError(f"{str(path)!r} is not a plain file of faultslip's (a link or a special file); remove it "
                         "and run again")


class RecordStream:
    """Float64 rows of ``width`` values appended to ``path`` (or kept in memory when ``path`` is None).

    ``rows_kept`` and ``digest`` resume a stream: the file's first ``rows_kept`` rows must hash to
    ``digest`` (what :meth:`digest` said at the checkpoint); what follows them is dropped.
    """

    def __init__(self, path, width: int, rows_kept: int = 0, digest: str | None = None):
        self.path = Path(path) if path is not None else None
        self.width, self.rows, self.buffer, self.memory = int(width), int(rows_kept), [], []
        self.buffered = 0  # rows in the buffer
        self.hasher = hashlib.sha256()
        self.descriptor = None
        if self.path is None:
            return
        if digest is None:
            self._create()
        else:
            self._reopen(digest)

    def _create(self) -> None:
        path = self.path
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)  # a planted link is removed, never followed
        try:
            self.descriptor = os.open(path, os.O_RDWR | os.O_APPEND | os.O_CREAT | os.O_EXCL | _FLAGS, 0o644)
        except OSError as exc:
            raise as_output_error(exc, path, path.parent) from None

    def _reopen(self, digest: str) -> None:
        path = self.path
        try:
            descriptor = os.open(path, os.O_RDWR | os.O_APPEND | _FLAGS)
        except FileNotFoundError:
            raise InputError(f"the record file {str(path)!r} of the run to resume is missing; {_RESUME}") from None
        except OSError as exc:
            raise _refuse_link(path, exc) from None
        _check_plain(descriptor, path)
        kept = self.rows * self.width * 8
        size = os.fstat(descriptor).st_size
        if size < kept:
            os.close(descriptor)
            raise InputError(f"the record file {str(path)!r} holds {size} bytes, fewer than the {kept} its checkpoint "
                             f"recorded: it was truncated; {_RESUME}")
        done = 0
        while done < kept:
            chunk = os.pread(descriptor, min(1 << 24, kept - done), done)
            if not chunk:
                break
            self.hasher.update(chunk)
            done += len(chunk)
        if self.hasher.hexdigest() != digest:
            os.close(descriptor)
            raise InputError(f"the record file {str(path)!r} does not match its checkpoint (it was changed or damaged "
                             f"after the checkpoint was written); {_RESUME}")
        os.ftruncate(descriptor, kept)  # rows written after the checkpoint are computed again
        self.descriptor = descriptor

    def append(self, row) -> None:
        self.buffer.append(row)
        self.rows += 1
        self.buffered += 1
        if self.buffered * self.width * 8 >= BUFFER_BYTES:
            self.flush()

    def extend(self, rows) -> None:
        """Append a block of rows (rows, width)."""
        self.buffer.append(rows)
        self.rows += len(rows)
        self.buffered += len(rows)
        if self.buffered * self.width * 8 >= BUFFER_BYTES:
            self.flush()

    def flush(self) -> None:
        if not self.buffer:
            return
        block = np.concatenate([np.asarray(rows, dtype=np.float64).reshape(-1, self.width) for rows in self.buffer])
        self.buffered = 0
        self.buffer = []
        if self.path is None:
            self.memory.append(block)
            return
        data = memoryview(block.tobytes())
        self.hasher.update(data)
        try:
            while data:
                data = data[os.write(self.descriptor, data):]
        except OSError as exc:
            raise as_output_error(exc, self.path, self.path.parent) from None

    def sync(self) -> None:
        """Flush and make durable: a checkpoint is written only after its streams are on disk."""
        self.flush()
        if self.descriptor is not None:
            try:
                os.fsync(self.descriptor)
            except OSError as exc:
                raise as_output_error(exc, self.path, self.path.parent) from None

    def digest(self) -> str:
        """SHA-256 of every row written so far (flush first)."""
        return self.hasher.hexdigest()

    def read(self) -> np.ndarray:
        """Every row, from the open descriptor (the path is not opened again)."""
        self.flush()
        if self.path is None:
            if len(self.memory) != 1:  # joined once, so that reading again costs no copy
                self.memory = [np.concatenate(self.memory) if self.memory else np.empty((0, self.width))]
            return self.memory[0]
        size = self.rows * self.width * 8
        data = bytearray()
        while len(data) < size:
            chunk = os.pread(self.descriptor, min(1 << 24, size - len(data)), len(data))
            if not chunk:
                raise InputError(f"the record file {str(self.path)!r} was truncated while the run wrote it")
            data += chunk
        return np.frombuffer(bytes(data), dtype=np.float64).reshape(-1, self.width)

    def columns(self, columns: slice):
        """Columns ``columns`` of every row: an array for a stream kept in memory; for a file, a
        :class:`RecordColumns` that reads it a block at a time, so that a long run's records stay on disk."""
        self.flush()
        if self.path is None:
            return self.read()[:, columns]
        return RecordColumns(self.path, self.width, self.rows, columns)

    def close(self) -> None:
        if self.descriptor is not None:
            with contextlib.suppress(OSError):
                os.close(self.descriptor)
            self.descriptor = None

    def remove(self) -> None:
        """Close and delete the file (a fresh run that failed leaves nothing behind)."""
        self.close()
        if self.path is not None:
            with contextlib.suppress(OSError):
                os.unlink(self.path)


class RecordColumns:
    """Read-only columns of a finished record file, read from disk when indexed.

    Indexing as numpy's on two dimensions (rows by an int, slice, mask or index array; columns by
    an int or slice) reads only the rows asked for, a block of :data:`BLOCK_BYTES` at a time, so
    that ``run.stations["slip"][:, k]`` over a run of centuries holds one column, never the file.
    ``numpy.asarray`` reads it all. :func:`lazy_data` hands it to xarray unread.
    """

    def __init__(self, path, width: int, rows: int, columns: slice = slice(None)):
        self.path, self.width, self.rows = Path(path), int(width), int(rows)
        self.selected = np.arange(self.width)[columns]
        self.shape = (self.rows, int(self.selected.size))
        self.ndim, self.dtype = 2, np.dtype(np.float64)
        self.nbytes = self.shape[0] * self.shape[1] * 8

    def __len__(self) -> int:
        return self.rows

    def __array__(self, dtype=None, copy=None):
        values = self[:, :]
        return values if dtype is None else values.astype(dtype)

    def __getitem__(self, key):
        key = key if isinstance(key, tuple) else (key,)
        if len(key) > 2 or any(part is Ellipsis or part is None for part in key):
            raise IndexError("a record's columns take at most a row and a column index")
        columns = self.selected[key[1] if len(key) == 2 else slice(None)]
        picked = np.arange(self.rows)[key[0]]
        single = picked.ndim == 0
        wanted, inverse = np.unique(np.atleast_1d(picked), return_inverse=True)
        per_block = max(1, BLOCK_BYTES // (8 * self.width))
        parts = []
        if wanted.size:
            descriptor = self._open()
            try:
                for block in np.unique(wanted // per_block):
                    rows = wanted[(wanted >= block * per_block) & (wanted < (block + 1) * per_block)]
                    first, last = int(rows[0]), int(rows[-1]) + 1
                    data = self._pread(descriptor, first, last)
                    if rows.size != last - first:  # only the rows asked for (a run of them needs no copy)
                        data = data[rows - first]
                    parts.append(data[:, columns].copy())  # a view would keep the whole block alive
            finally:
                os.close(descriptor)
        shape = (0,) + np.empty((0, self.width))[:, columns].shape[1:]
        values = np.concatenate(parts)[inverse.ravel()] if parts else np.empty(shape)
        return values[0] if single else values

    def _open(self) -> int:
        try:
            return os.open(self.path, os.O_RDONLY | _FLAGS)
        except FileNotFoundError:
            raise InputError(f"the record file {str(self.path)!r} of this run is gone (its output folder was "
                             "changed); run it again") from None
        except OSError as exc:
            raise _refuse_link(self.path, exc) from None

    def _pread(self, descriptor: int, first: int, last: int) -> np.ndarray:
        """Rows ``first`` to ``last`` read straight into one array (no intermediate copies)."""
        data = np.empty((last - first, self.width))
        view, offset = memoryview(data).cast("B"), first * self.width * 8
        done = 0
        while done < view.nbytes:
            count = os.preadv(descriptor, [view[done:]], offset + done)
            if count == 0:
                raise InputError(f"the record file {str(self.path)!r} was truncated after the run wrote it; run it "
                                 "again")
            done += count
        return data


def lazy_data(values):
    """``values`` as xarray takes data: a :class:`RecordColumns` wrapped so that xarray reads it only
    when indexed or written (a block at a time by :func:`faultslip.io.netcdf.write_dataset`); an array
    as it is."""
    if not isinstance(values, RecordColumns):
        return values
    from xarray.backends import BackendArray  # heavy: imported where used
    from xarray.core import indexing  # heavy: imported where used

    class _Backend(BackendArray):
        shape, dtype = values.shape, values.dtype

        def __getitem__(self, key):
            return indexing.explicit_indexing_adapter(key, self.shape, indexing.IndexingSupport.BASIC,
                                                      values.__getitem__)

    return indexing.LazilyIndexedArray(_Backend())


def _checksum(arrays: dict) -> str:
    digest = hashlib.sha256()
    for key in sorted(arrays):
        value = np.ascontiguousarray(arrays[key])
        digest.update(f"{key}|{value.dtype.str}|{value.shape}|".encode())
        digest.update(value.tobytes())
    return digest.hexdigest()


def write_checkpoint(path, **arrays) -> None:
    """Save ``arrays`` (numbers and strings) to ``path`` atomically with their SHA-256."""
    arrays = {key: np.asarray(value) for key, value in arrays.items()}
    with atomic_path(path, immediate=True) as temporary:
        descriptor = os.open(temporary, os.O_WRONLY | os.O_TRUNC | _FLAGS)
        with os.fdopen(descriptor, "wb") as handle:
            np.savez(handle, checksum=np.asarray(_checksum(arrays)), **arrays)
            handle.flush()
            os.fsync(handle.fileno())


def check_npy_headers(archive, path, label: str) -> None:
    """Every ``.npy`` member of an ``.npz`` archive from :func:`open_zip` declares no more than it holds: its
    header's shape times its item size is at most the member's declared size, and its type holds no Python
    objects. Read before numpy allocates an array from the header."""
    name = Path(path).name
    for info in archive.infolist():
        if not info.filename.endswith(".npy"):
            raise InputError(f"{label} {name}: member {info.filename!r} is not an array (.npy)")
        with gate.decoding(path, label, f"the header of {info.filename}"):
            with archive.open(info) as stream:
                version = np.lib.format.read_magic(stream)
                reader = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                          else np.lib.format.read_array_header_2_0)
                shape, _, dtype = reader(stream, max_header_size=10_000)
        if dtype.hasobject:
            raise InputError(f"{label} {name}: member {info.filename!r} holds Python objects, never loaded")
        count = 1
        for extent in shape:
            count *= int(extent)
        if count * dtype.itemsize > info.file_size:
            raise InputError(f"{label} {name}: member {info.filename!r} declares {shape} of {dtype}, more than its "
                             f"{gate.size_text(info.file_size)} hold")


def read_checkpoint(path, layout: dict, what: str = "checkpoint") -> dict:
    """The arrays of the checkpoint at ``path``, checked against its digest and ``layout``.

    ``layout`` maps each name to its expected (dtype kind, shape) with ``None`` for any length.
    Whatever is wrong (not a zip, a member missing or of another shape, a digest that does not
    match) is one :class:`InputError` naming the file.
    """
    path = Path(path)
    label = f"the {what}"
    if path.is_symlink():
        raise InputError(f"{label} {str(path)!r} is a symbolic link, which faultslip never follows; {_RESUME}")
    data = gate.read_bytes(path, label, "netcdf")
    if not data:
        raise InputError(f"{label} {str(path)!r} is empty; {_RESUME}")
    # bounded before numpy allocates: the members' declared sizes and ratios, then each array header against them
    check_npy_headers(gate.open_zip(data, path, label, total_limit=gate.LIMITS["netcdf"]), path, label)
    with gate.decoding(path, label, "a faultslip checkpoint"):
        with np.load(io.BytesIO(data), allow_pickle=False) as archive:
            saved = {key: archive[key] for key in archive.files}
    stored = saved.pop("checksum", None)
    if stored is None or stored.shape != () or stored.dtype.kind != "U":
        raise InputError(f"{label} {str(path)!r} carries no checksum: it was not written by this faultslip, or was "
                         f"saved again; {_RESUME}")
    if str(stored) != _checksum(saved):
        raise InputError(f"{label} {str(path)!r} does not match its checksum (it was damaged or changed); {_RESUME}")
    for key, (kind, shape) in layout.items():
        value = saved.get(key)
        ok = value is not None and value.dtype.kind in kind and value.ndim == len(shape) and all(
            want is None or have == want for have, want in zip(value.shape, shape))
        if not ok:
            found = "missing" if value is None else f"{value.dtype} {value.shape}"
            raise InputError(f"{label} {str(path)!r} does not hold what a checkpoint of this run holds ({key}: "
                             f"{found}); {_RESUME}")
    return saved
