"""One way out: every file faultslip writes passes :func:`atomic_path`.

It holds the output's lock (:func:`faultslip.io.outputs.output_lock`, taken here unless the run
already holds it), writes to a temporary file in the target's folder and renames it into place.
An interrupted run therefore leaves either nothing or the complete previous file under the
final name, never a truncated one; a full disk (ENOSPC, or the HDF5 and netCDF libraries' own
words for it) becomes one sentence and leaves no partial file.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import shutil
from pathlib import Path

from faultslip.errors import InputError
from faultslip.io.outputs import as_output_error, disk_is_full, full_disk_error, output_lock, refuse_links


#: Renames deferred by an open :func:`transaction`: (temporary, target) pairs.
_PENDING: list | None = None
#: The locks an open transaction holds until its end (:func:`claim`).
_CLAIMS: contextlib.ExitStack | None = None


def claim(path, command: str = "faultslip", overwrite: bool = True, label: str = "-o") -> None:
    """Take the lock of an output at the start of a command and hold it to the transaction's end.

    The existence check is made under the lock (see :func:`faultslip.io.outputs.output_lock`):
    a second writer of any kind, or an output that appeared meanwhile, is refused before any work.
    Outside a transaction the lock is taken and released at once (a check only).
    """
    if _CLAIMS is None:
        with output_lock(path, command, overwrite, label):
            return
    _CLAIMS.enter_context(output_lock(path, command, overwrite, label))


@contextlib.contextmanager
def transaction():
    """Every output written inside appears at the end, together, or none does.

    The CLI runs each command in one: a run that writes a netCDF file and then fails on its
    figure (a full disk, a bad option found late) leaves neither behind. Nested transactions
    join the outermost.
    """
    global _PENDING, _CLAIMS
    if _PENDING is not None:
        yield
        return
    _PENDING = pending = []
    with contextlib.ExitStack() as claims:  # released last, after the renames
        _CLAIMS = claims
        try:
            yield
            _PENDING = None
            for temporary, target in pending:
                os.replace(temporary, target)
        except BaseException:
            for temporary, _ in pending:
                with contextlib.suppress(OSError):
                    os.unlink(temporary)
            raise
        finally:
            _PENDING, _CLAIMS = None, None


@contextlib.contextmanager
def atomic_path(path, suffix: str | None = None, immediate: bool = False):
    """Yield a temporary path next to ``path``; on success rename it over ``path``.

    On any exception (including KeyboardInterrupt) the temporary file is
    removed and ``path`` is untouched. Inside a :func:`transaction` the rename waits for the
    transaction's end, unless ``immediate`` (a progress record, a registry updated under its lock).
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise InputError(f"output directory {str(directory)!r} does not exist")
    with output_lock(target, "faultslip"):
        try:
            temporary = _new_temporary(directory, target.name,
                                       suffix if suffix is not None else (target.suffix or ".tmp") + ".tmp")
        except OSError as exc:
            raise as_output_error(exc, target, directory) from None
        try:
            yield Path(temporary)
            os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes 0600; a normal file respects the umask
            if _PENDING is not None and not immediate:
                _PENDING.append((temporary, target))
            else:
                os.replace(temporary, target)
        except BaseException as exc:
            full = disk_is_full(exc, directory)
            with contextlib.suppress(FileNotFoundError):
                os.unlink(temporary)
            if full:
                raise full_disk_error(target, directory) from None
            raise


_SERIAL = itertools.count()


def _new_temporary(directory: Path, name: str, suffix: str) -> str:
    """A new empty file ``.NAME.PID.N{suffix}`` in ``directory``, created with O_EXCL (as mkstemp, without
    importing tempfile's random machinery into every command's start)."""
    while True:
        path = directory / f".{name}.{os.getpid()}.{next(_SERIAL)}{suffix}"
        try:
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600))
            return str(path)
        except FileExistsError:
            continue


def _umask() -> int:
    current = os.umask(0)
    os.umask(current)
    return current


def write_text_atomic(path, text: str, immediate: bool = False) -> None:
    with atomic_path(path, immediate=immediate) as temporary:
        temporary.write_text(text, encoding="utf-8")


def write_chunks_atomic(path, chunks) -> None:
    """Write the text ``chunks`` (an iterable of strings) to ``path`` atomically, one at a time, so that a
    long file is never held whole in memory."""
    with atomic_path(path) as temporary:
        with open(temporary, "w", encoding="utf-8") as handle:
            for chunk in chunks:
                handle.write(chunk)


def save_figure(figure, path, **kwargs) -> None:
    """Save a matplotlib figure atomically; the format follows the file name."""
    target = Path(path)
    fmt = target.suffix.lstrip(".").lower() or "png"
    with atomic_path(target) as temporary:
        figure.savefig(temporary, format=fmt, **kwargs)
    import matplotlib.pyplot as plt  # heavy: matplotlib only once a figure exists

    plt.close(figure)  # a saved figure is done with; pyplot would otherwise keep every one open


def save_frames(frames, path, duration_ms: int) -> None:
    """Save pillow images as an animated GIF (``duration_ms`` a frame, looping), atomically."""
    with atomic_path(path, suffix=".gif") as temporary:
        frames[0].save(str(temporary), format="GIF", save_all=True, append_images=frames[1:], duration=duration_ms,
                       loop=0)


@contextlib.contextmanager
def partial_output(target):
    """The guard of an output written in place over many steps as ``TARGET.partial`` (a conversion).

    The caller holds the output's lock and renames the partial into place when it is complete. On
    any failure the partial is removed; a full disk is one sentence.
    """
    target = Path(target)
    partial = target.with_name(target.name + ".partial")
    directory = target.parent if str(target.parent) else Path(".")
    refuse_links(partial)
    try:
        yield partial
    except BaseException as exc:
        full = disk_is_full(exc, directory)
        partial.unlink(missing_ok=True)
        if full:
            raise full_disk_error(target, directory) from None
        raise


def commit(partial, target) -> None:
    """Rename a complete ``partial`` (written in place over many steps, under the output's lock) onto
    ``target``: the one rename of such outputs; a failure is one sentence."""
    target = Path(target)
    directory = target.parent if str(target.parent) else Path(".")
    refuse_links(partial)  # a planted link would become the output, pointing out of its folder
    try:
        os.replace(partial, target)
    except OSError as exc:
        raise as_output_error(exc, target, directory) from None



def working_copy(target, partial) -> None:
    """Copy an existing output ``target`` (a file, or a folder such as a Zarr store) to ``partial``, to be changed
    in place and then put back by :func:`commit` (or, for a store, its own rename): an update that is interrupted
    leaves ``target`` as it was. A failure (a full disk) is one sentence."""
    target, partial = Path(target), Path(partial)
    directory = target.parent if str(target.parent) else Path(".")
    try:
        if target.is_dir():
            shutil.copytree(target, partial)
        else:
            shutil.copyfile(target, partial)
    except OSError as exc:
        if partial.is_dir():
            shutil.rmtree(partial, ignore_errors=True)
        else:
            partial.unlink(missing_ok=True)
        raise as_output_error(exc, target, directory) from None
