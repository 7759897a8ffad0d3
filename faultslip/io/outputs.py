"""Output files: checked before any work starts, and locked against a second writer.

:func:`check_output` refuses, in one sentence and before anything is computed, an output whose
folder is missing, that names a folder, has the wrong extension, already exists (unless the
caller passes ``overwrite``) or is also one of the inputs. :func:`output_lock` holds an exclusive
``flock`` on ``.NAME.lock`` beside the output for as long as the output is being written; a
second faultslip run that wants the same output is refused, naming the process that holds it.
The kernel drops a lock when its process dies, so a crashed run never leaves a stale lock.
"""

from __future__ import annotations

import contextlib
import json
import os
import time
from pathlib import Path

from faultslip.errors import InputError
from faultslip.io.zarr_store import is_store

#: Image formats matplotlib writes (its Agg, PDF, PS and SVG backends).
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg", ".eps", ".ps", ".tif", ".tiff", ".webp")


def same_file(a, b) -> bool:
    """Whether two paths name one file (resolving links and ``..``; a missing file is compared by path)."""
    a, b = Path(a), Path(b)
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def check_output(path, *, label: str, suffixes=None, inputs=(), overwrite: bool = False,
                 directory: bool = False, store: bool = False) -> Path:
    """Refuse an unusable output path before any work starts; returns it as a Path.

    ``suffixes`` lists the allowed endings (None: any); ``inputs`` are files this run reads;
    ``directory`` means ``path`` is a folder to write into (created if its parent exists);
    ``store`` means ``path`` is a Zarr store (a folder written whole): an existing one is replaced
    only with ``overwrite``, and a folder that is not a store never.
    """
    target = Path(path)
    if not str(path).strip():
        raise InputError(f"{label}: the output path is empty")
    if store and target.exists():
        if not is_store(target):
            what = "a folder" if target.is_dir() else "a file"
            raise InputError(f"{label} {str(target)!r} is {what} but not a Zarr store; choose another output")
        if not overwrite:
            raise InputError(f"{label} {str(target)!r} already exists; pass --overwrite to replace it")
        overwrite, target_is_store = True, True
    else:
        target_is_store = False
    if directory:
        if target.exists() and not target.is_dir():
            raise InputError(f"{label} {str(target)!r} is a file, not a folder")
        if not target.exists() and not target.parent.is_dir():
            raise InputError(f"{label}: the folder {str(target.parent)!r} that would hold {target.name!r} does not exist")
        return target
    parent = target.parent
    if target.is_dir() and not target_is_store:
        raise InputError(f"{label} {str(target)!r} is a folder; give a file name inside it")
    if not parent.is_dir():
        what = "is a file, not a folder" if parent.exists() else "does not exist"
        raise InputError(f"{label}: the folder {str(parent)!r} {what}")
    if suffixes is not None and target.suffix.lower() not in suffixes:
        raise InputError(f"{label} {str(target)!r} must end in {', '.join(suffixes)}")
    for source in inputs:
        if source is not None and same_file(target, source):
            raise InputError(f"{label} {str(target)!r} is also an input of this run; choose another output")
    if target.exists() and not overwrite:
        raise InputError(f"{label} {str(target)!r} already exists; pass --overwrite to replace it")
    if not os.access(parent, os.W_OK):
        raise InputError(f"{label}: the folder {str(parent)!r} is not writable")
    return target


def _lock_path(target: Path) -> Path:
    return target.with_name(f".{target.name}.lock")


@contextlib.contextmanager
def output_lock(path, command: str = "faultslip"):
    """Hold an exclusive lock on ``path`` as an output; a second holder gets an :class:`InputError`.

    The lock file records the holder's pid, command and start time, which the refusal quotes.
    Without ``fcntl`` (Windows) the lock is a no-op.
    """
    try:
        import fcntl
    except ImportError:  # no flock: nothing to hold
        yield
        return
    target = Path(path)
    lock = _lock_path(target)
    while True:
        handle = open(lock, "a+", encoding="utf-8")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.seek(0)
            holder = _describe_holder(handle.read())
            handle.close()
            raise InputError(f"{target.name} is being written by another faultslip run ({holder}); "
                             "wait for it to finish or choose another output") from None
        # the file we locked may have been unlinked by a holder that just finished: lock the new one
        try:
            if os.fstat(handle.fileno()).st_ino == os.stat(lock).st_ino:
                break
        except FileNotFoundError:
            pass
        handle.close()
    handle.seek(0)
    handle.truncate()
    handle.write(json.dumps({"pid": os.getpid(), "command": command, "started": time.time()}))
    handle.flush()
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock)
        handle.close()


def _describe_holder(text: str) -> str:
    try:
        record = json.loads(text)
        started = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(float(record["started"])))
        return f"pid {int(record['pid'])}, '{record.get('command', 'faultslip')}', started {started}"
    except (ValueError, KeyError, TypeError):
        return "another process"


@contextlib.contextmanager
def file_lock(path, timeout: float = 30.0):
    """Wait (up to ``timeout`` s) for an exclusive lock on ``path``: read-modify-write of shared files."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    lock = _lock_path(target)
    deadline = time.monotonic() + timeout
    with open(lock, "a+", encoding="utf-8") as handle:
        while True:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() > deadline:
                    raise InputError(f"{target.name} is locked by another faultslip run for more than {timeout:g} s; "
                                     "try again when it has finished") from None
                time.sleep(0.02)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)
