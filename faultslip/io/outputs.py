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
import errno
import json
import os
import shutil
import stat
import time
from pathlib import Path

from faultslip.errors import InputError, OutputError

#: Files that mark a folder as a Zarr store (format 2 or 3): only such a folder is ever replaced.
_MARKERS = (".zgroup", ".zmetadata", "zarr.json")


def is_store(path) -> bool:
    """Whether ``path`` is a folder holding a Zarr store."""
    path = Path(path)
    return path.is_dir() and any((path / marker).exists() for marker in _MARKERS)


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
    check_encodable(target, label)
    check_name_length(target, label)
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


def refuse_links(*paths, label: str = "") -> None:
    """Refuse, in one sentence, any of ``paths`` that is a symbolic link: a partial output, a ledger, a lock or a
    work folder that faultslip would write through is never followed out of its folder (the 2-D streams' rule,
    for every output)."""
    for path in paths:
        path = Path(path)
        if path.is_symlink():
            raise InputError(f"{label + ': ' if label else ''}{str(path)!r} is a symbolic link, which faultslip never "
                             "follows; remove it and run again")


def check_encodable(path, label: str) -> Path:
    """Refuse a path that is not valid UTF-8 (bytes the file system allows but netCDF-C, HDF5 and the
    formats' own metadata cannot name): one sentence before any work, instead of netCDF4's
    UnicodeEncodeError after it."""
    text = os.fsdecode(os.fspath(path))
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        shown = text.encode("utf-8", "backslashreplace").decode("ascii", "backslashreplace")
        raise InputError(f"{label} {shown!r} is not valid UTF-8 (the netCDF library cannot name such a file); "
                         "choose a name in UTF-8") from None
    return Path(path)


#: Bytes faultslip adds to an output's name for the files it writes beside it (``.NAME.PID.N.nc.tmp``, ``.NAME.lock``,
#: a partial output's ledger, an NRML file's logic trees beside it): a name that fits alone but not with these would
#: fail after the work.
NAME_MARGIN = 64


def check_name_length(path, label: str) -> Path:
    """Refuse an output whose name, with :data:`NAME_MARGIN` for the temporary and lock files beside it, or any
    folder of whose path, is longer than the file system takes (``NAME_MAX``, ``PATH_MAX``): one sentence before
    any work, not the system's "File name too long" after it."""
    target = Path(path)
    try:  # the limits of the file system the output goes to (a missing folder: the current one's)
        anchor = target.parent if _is_dir(target.parent) else Path.cwd()
        name_max, path_max = os.pathconf(anchor, "PC_NAME_MAX"), os.pathconf(anchor, "PC_PATH_MAX")
    except (OSError, ValueError):
        name_max, path_max = 255, 4096
    shown = str(target) if len(str(target)) <= 80 else f"{str(target)[:60]}...{str(target)[-17:]}"
    for part in target.parts[:-1]:
        if len(os.fsencode(part)) > name_max:
            raise InputError(f"{label} {shown!r} has a folder name of {len(os.fsencode(part))} bytes; this file "
                             f"system takes at most {name_max}")
    length = len(os.fsencode(target.name))
    if length + NAME_MARGIN > name_max:
        raise InputError(f"{label} {shown!r} has a name of {length} bytes; this file system takes {name_max}, and "
                         f"faultslip needs {NAME_MARGIN} more for the temporary file beside it: choose a name of at "
                         f"most {name_max - NAME_MARGIN}")
    if len(os.fsencode(os.path.abspath(target))) + NAME_MARGIN > path_max:
        raise InputError(f"{label} {shown!r} is a path longer than this file system takes ({path_max} bytes, with "
                         f"{NAME_MARGIN} for the temporary file beside it)")
    return target


def _is_dir(folder: Path) -> bool:
    try:
        return folder.is_dir()
    except OSError:  # a name the system cannot look up
        return False


#: Free bytes below which a failed write is put down to a full disk (HDF5 says only "HDF error").
NEARLY_FULL = 4 * 2**20


def prepare_run_folder(folder: Path, *, resume: bool, overwrite: bool, what: str) -> bool:
    """Check a run's ``--output-dir`` before any work and make it; True where this call created it (a failed run
    removes a folder it made). A checkpointed run's folder (``checkpoint.npz``) may be resumed; any other
    non-empty folder needs ``overwrite``; a file, a link, a missing parent or a folder one cannot write is refused
    in one sentence."""
    check_name_length(folder, "--output-dir")
    if folder.exists() and not folder.is_dir():
        raise InputError(f"--output-dir {folder} is a file; give a folder for the run's files")
    checkpointed = (folder / "checkpoint.npz").is_file()
    if resume and not checkpointed:
        raise InputError(f"--resume: {folder} holds no checkpoint of {what} (a run stopped before its first "
                         "checkpoint leaves none); start it without --resume")
    if not resume and folder.is_dir() and any(folder.iterdir()) and not overwrite:
        raise InputError(f"--output-dir {folder} is not empty; " + (
            "pass --resume to continue the run it holds, or --overwrite to start again" if checkpointed else
            "it holds no checkpoint to resume: pass --overwrite to start again, or choose an empty folder"))
    check_encodable(folder, "--output-dir")
    if folder.is_symlink():
        raise InputError(f"--output-dir {folder} is a symbolic link, which faultslip never follows; give the "
                         "folder itself")
    created = not folder.exists()
    if created and not folder.parent.is_dir():
        raise InputError(f"--output-dir: the folder {str(folder.parent)!r} that would hold {folder.name!r} "
                         "does not exist")
    if not os.access(folder if not created else folder.parent, os.W_OK | os.X_OK):
        raise InputError(f"--output-dir {folder} is not writable; choose a folder you can write to")
    folder.mkdir(exist_ok=True)
    return created


def disk_is_full(exc: BaseException, directory) -> bool:
    """Whether ``exc``, raised while writing into ``directory``, means the disk is full."""
    if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    if isinstance(exc, (KeyboardInterrupt, SystemExit, MemoryError)):
        return False
    try:  # HDF5, netCDF-C, zarr and PIL report a full disk in their own words: ask the disk
        return shutil.disk_usage(directory).free < NEARLY_FULL
    except OSError:
        return False


def full_disk_error(target, directory) -> OutputError:
    try:
        free = f"{shutil.disk_usage(directory).free / 1e3:.0f} kB free"
    except OSError:
        free = "no space"
    return OutputError(f"the disk holding {str(directory)!r} is full ({free}) while writing {Path(target).name}; "
                       "nothing was left behind; free some space or choose another folder")


def as_output_error(exc: OSError, target, directory) -> OutputError:
    if disk_is_full(exc, directory):
        return full_disk_error(target, directory)
    return OutputError(f"cannot write {str(target)!r}: {exc.strerror or exc}")


def _lock_path(target: Path) -> Path:
    return target.with_name(f".{target.name}.lock")


#: Lock paths this process holds: a nested claim of one output (a command's claim, then its write) reuses it.
_HELD: set = set()


def _open_lock(lock: Path, attempts: int = 100) -> int:
    """A descriptor on the lock file, created if absent; never through a symlink, never a foreign file.

    ``O_CREAT|O_EXCL|O_NOFOLLOW`` creates it without following anything planted at its path; an
    existing one is opened with ``O_NOFOLLOW`` and must be a regular file with one link (a planted
    symlink, FIFO or hard link to another file is refused, and nothing is truncated). A holder that
    finishes removes its lock: one that vanishes between the two opens is created afresh.
    """
    flags = os.O_RDWR | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    for _ in range(attempts):
        try:
            return os.open(lock, flags | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            pass
        except OSError as exc:
            if disk_is_full(exc, lock.parent):
                raise full_disk_error(lock, lock.parent) from None
            raise OutputError(f"cannot create the lock {str(lock)!r}: {exc.strerror or exc}") from None
        try:
            descriptor = os.open(lock, flags)
            break
        except FileNotFoundError:  # removed by its holder after our create found it: create it again
            continue
        except OSError as exc:
            if exc.errno == errno.ELOOP or lock.is_symlink():
                raise InputError(f"the lock file {str(lock)!r} is a symbolic link, which faultslip never follows; "
                                 "remove it and run again") from None
            raise InputError(f"cannot take the lock {str(lock)!r}: {exc.strerror or exc}") from None
    else:
        raise InputError(f"cannot take the lock {str(lock)!r}: other runs create and remove it faster than it "
                         "can be opened; run again")
    info = os.fstat(descriptor)
    # one link: ours; none: a holder that just finished unlinked it (output_lock sees the inode change and
    # opens the new one); more: a hard link planted to another file
    if not stat.S_ISREG(info.st_mode) or info.st_nlink > 1:
        os.close(descriptor)
        raise InputError(f"the lock file {str(lock)!r} is not a plain file of faultslip's (a link or a special "
                         "file); remove it and run again")
    return descriptor


@contextlib.contextmanager
def output_lock(path, command: str = "faultslip", overwrite: bool = True, label: str = "-o", wait: float = 0.0):
    """Hold an exclusive lock on ``path`` as an output; a second holder gets an :class:`InputError`.

    The lock and the existence check are taken together: once the lock is held, an output that
    exists is refused unless ``overwrite`` (so two runs cannot both find it absent and write it).
    The lock file records the holder's pid, command and start time, which the refusal quotes;
    ``flock`` on it means a killed holder leaves no stale lock. Claims nest within one process.
    ``wait`` > 0 waits that many seconds for a holder to finish instead of refusing at once (a
    read-modify-write of a shared file such as the fit registry). Without ``fcntl`` (Windows)
    only the existence check is made.
    """
    target = Path(path)
    lock = _lock_path(target)
    key = str(lock.resolve(strict=False)) if not lock.is_symlink() else str(lock)
    if key in _HELD:
        yield
        return
    try:
        import fcntl
    except ImportError:  # no flock: nothing to hold
        fcntl = None
    descriptor = None
    deadline = time.monotonic() + wait
    if fcntl is not None:
        while True:
            descriptor = _open_lock(lock)
            try:
                fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.lseek(descriptor, 0, os.SEEK_SET)
                holder = _describe_holder(os.read(descriptor, 4096).decode("utf-8", "replace"))
                os.close(descriptor)
                if time.monotonic() < deadline:
                    time.sleep(0.02)
                    continue
                raise InputError(f"{target.name} is being written by another faultslip run ({holder}); "
                                 + ("try again when it has finished" if wait else
                                    "wait for it to finish or choose another output")) from None
            # the file we locked may have been unlinked by a holder that just finished: lock the new one
            try:
                if os.fstat(descriptor).st_ino == os.stat(lock, follow_symlinks=False).st_ino:
                    break
            except FileNotFoundError:
                pass
            os.close(descriptor)
    try:
        if not overwrite and (target.exists() or target.is_symlink()):
            raise InputError(f"{label} {str(target)!r} already exists; pass --overwrite to replace it")
        if descriptor is not None:
            try:
                os.ftruncate(descriptor, 0)
                os.lseek(descriptor, 0, os.SEEK_SET)
                os.write(descriptor, json.dumps({"pid": os.getpid(), "command": command,
                                                 "started": time.time()}).encode())
            except OSError as exc:  # the holder's record is a courtesy; a full disk is not
                if disk_is_full(exc, lock.parent):
                    raise full_disk_error(target, lock.parent) from None
                raise
        _HELD.add(key)
        try:
            yield
        finally:
            _HELD.discard(key)
    finally:
        if descriptor is not None:
            with contextlib.suppress(OSError):
                if os.fstat(descriptor).st_ino == os.stat(lock, follow_symlinks=False).st_ino:
                    os.unlink(lock)
            os.close(descriptor)


def _describe_holder(text: str) -> str:
    try:
        record = json.loads(text)
        started = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(float(record["started"])))
        return f"pid {int(record['pid'])}, '{record.get('command', 'faultslip')}', started {started}"
    except (ValueError, KeyError, TypeError):
        return "another process"


def file_lock(path, timeout: float = 30.0):
    """Wait (up to ``timeout`` s) for the lock of a shared file that is read, changed and written again."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    return output_lock(path, "faultslip (shared file)", wait=timeout)
