"""Worker processes that die with their parent, and a Ctrl-C that stops everything cleanly.

A worker of :func:`worker_pool` ignores SIGINT (Ctrl-C reaches the whole process group, and only
the parent should answer it: one line, exit 130) and is killed by the kernel when its parent dies,
whatever killed the parent (``kill -9`` included): ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux,
and everywhere a watchdog thread that exits once the parent is gone. :func:`stop_pool` terminates
the workers instead of waiting for their tasks, so an interrupt never waits on, or deadlocks with,
a busy pool.
"""

from __future__ import annotations

import atexit
import contextlib

import ctypes
import itertools
import os
import signal
import sys
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures import wait as futures_wait
from faultslip.errors import InputError

_PR_SET_PDEATHSIG = 1
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3  # glibc's mallopt parameters (malloc.h)


def is_alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie is not alive), on any platform psutil knows."""
    import psutil  # heavy: imported where used (only the watchdog and its tests ask)

    try:
        return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


def children(pid: int) -> list[int]:
    """Live child processes of ``pid``, e.g. to check that a pool's workers are gone."""
    import psutil  # heavy: imported where used

    try:
        found = psutil.Process(pid).children()
    except psutil.Error:
        return []
    alive = []
    for child in found:
        try:
            if child.status() != psutil.STATUS_ZOMBIE:
                alive.append(child.pid)
        except psutil.Error:  # gone between the listing and the look
            pass
    return alive


def usable_cores() -> int:
    """The cores this process may run on: its CPU affinity where the platform keeps one (``taskset``, a
    container's or a SLURM job's cpuset), else every core of the machine. ``os.cpu_count`` alone counts the
    machine's, and a process held to one of them would start a worker or a thread for each."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # no affinity here (macOS, Windows): the machine's cores
        return os.cpu_count() or 1


def usable_workers(requested: int, tasks: int | None = None) -> tuple[int, str]:
    """``(workers, note)``: ``requested`` capped at the cores and the tasks; the note says why, or is ''.

    More processes than cores only add start-up time and memory; more than tasks stay idle.
    """

    if requested < 1:
        raise InputError(f"--workers must be at least 1, got {requested}")
    cores = usable_cores()
    limit = min(cores, tasks) if tasks is not None else cores
    limit = max(limit, 1)
    if requested <= limit:
        return requested, ""
    why = f"{cores} usable core{'s' if cores != 1 else ''}" if limit == cores else f"{tasks} chunks of work"
    return limit, f"--workers {requested} capped at {limit} ({why}: more would not run faster)"


def retain_freed_memory() -> bool:
    """Let this process reuse the memory it frees instead of returning it to the kernel (glibc; elsewhere a
    no-op returning False).

    A sweep's block allocates the same tens of MB of arrays again and again. By default glibc maps each
    array of over 128 kB afresh and unmaps it when freed, so every block pays page faults and zeroing
    on all of it: measured, a 1e7-cell sweep spent 30 % of its CPU in the kernel (1.4 s of 5 s in one
    process). Arrays below 32 MB (glibc's largest threshold) now come from the heap, which keeps up to
    1 GB freed for the next block: 0.07 s in the kernel, and the same peak memory, since each block
    reuses the last one's.
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None)
        return bool(libc.mallopt(_M_MMAP_THRESHOLD, 32 << 20) and libc.mallopt(_M_TRIM_THRESHOLD, 1 << 30))
    except (OSError, AttributeError):  # not glibc (musl has no mallopt): its defaults stand
        return False


#: Threads a worker's own run may use (a 2-D fault's kernels): a pool's workers already fill the cores, one each.
THREADS_VARIABLE = "FAULTSLIP_THREADS"


def threads_for(elements: int, pays_from: int) -> int:
    """Threads for one run's kernels: ``FAULTSLIP_THREADS`` where set (a pool's worker sets 1), else every usable
    core (:func:`usable_cores`) once the run is big enough for threads to pay (``elements`` >= ``pays_from``),
    else 1."""
    value = _threads_setting()
    if value:
        try:
            chosen = int(value)
        except ValueError:
            raise InputError(f"{THREADS_VARIABLE} must be a whole number of threads, got {value!r}") from None
        if chosen < 1:
            raise InputError(f"{THREADS_VARIABLE} must be at least 1, got {chosen}")
        return chosen
    return usable_cores() if elements >= pays_from else 1


def _threads_setting() -> str:
    """``FAULTSLIP_THREADS`` as set, stripped; '' where it is not."""
    return os.environ.get(THREADS_VARIABLE, "").strip()


def threads_are_automatic() -> bool:
    """Whether :func:`threads_for` chooses the threads itself (``FAULTSLIP_THREADS`` unset): such a run may then
    change its mind as the machine's load changes."""
    return not _threads_setting()


def _die_with_parent(parent: int) -> None:
    """Worker initializer: ignore Ctrl-C, reuse freed memory, use one thread a run, and exit when the parent
    process is gone."""
    os.environ.setdefault(THREADS_VARIABLE, "1")  # the pool's workers fill the cores; more threads would oversubscribe
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    retain_freed_memory()
    if hasattr(signal, "pthread_sigmask"):  # held back while this worker was forked (see worker_pool)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
        except (OSError, AttributeError):  # no prctl: the watchdog below still works
            pass
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)

    def watchdog():
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watchdog, daemon=True, name="faultslip-parent-watchdog").start()


def _ready() -> bool:
    return True


def worker_pool(workers: int) -> ProcessPoolExecutor:
    """A process pool whose workers ignore SIGINT and die with this process.

    The workers are forked at once, with SIGINT blocked: a Ctrl-C that lands during a fork would
    otherwise raise KeyboardInterrupt inside the at-fork handlers, where Python ignores it (the
    run went on) or, in a child that has not yet become a worker, unwinds into the CLI's handler
    (found by benchmarks/kills.py). A Ctrl-C held back is delivered as soon as the fork is done.
    """
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_die_with_parent, initargs=(os.getpid(),))
    if hasattr(signal, "pthread_sigmask") and threading.current_thread() is threading.main_thread():
        held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            pool.submit(_ready).result()  # with the fork start method this forks every worker now
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)
    return pool


def descendants() -> list:
    """This process's descendants now (psutil Processes): what a cluster started, to be reaped after it closes."""
    import psutil  # heavy: imported where used

    try:
        return psutil.Process().children(recursive=True)
    except psutil.Error:
        return []


def reap(processes, timeout: float = 10.0) -> None:
    """Wait up to ``timeout`` s for ``processes`` to exit, then kill those left: nothing a run started outlives
    it (a dask LocalCluster's nanny returns before its worker process has gone). A multiprocessing resource
    tracker is left alone: it is the process's own, shared with what else it runs, and it exits by itself, its
    clean-up done, when the process does."""
    import psutil  # heavy: imported where used

    def tracker(process):
        try:
            return "resource_tracker" in " ".join(process.cmdline())
        except psutil.Error:
            return True  # gone already

    workers = [process for process in processes if not tracker(process)]
    _, alive = psutil.wait_procs(workers, timeout=timeout)
    for process in alive:
        try:
            process.kill()
        except psutil.Error:
            pass
    psutil.wait_procs(alive, timeout=timeout)


def stop_pool(pool, interrupted: bool = False) -> None:
    """Shut a pool down; after an interrupt or error, terminate its workers rather than wait for them."""
    if pool is None:
        return
    if interrupted:
        processes = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            if process.is_alive():
                process.terminate()
        for process in processes:
            process.join(timeout=5)
    else:
        pool.shutdown(cancel_futures=True)


def run_windowed(executor, task, items, handle, *, window: int, on_tick=None, on_error=None) -> None:
    """Run ``task(*args)`` for each ``(key, args)`` of ``items``; ``handle(key, result)`` in this process.

    ``executor`` is None (in this process, in order), a process pool or a dask Client. At most
    ``window`` tasks are in flight, so memory stays flat however many items there are.
    ``on_tick()`` runs after every handled batch (progress records, periodic flushes). With ``on_error``, a task
    that raises an :class:`Exception` (a dask worker that died too often included) calls ``on_error(key, exc)``
    and the others go on; without it, the exception ends the run.
    """

    def settle(key, outcome):
        try:
            result = outcome()
        except Exception as exc:  # noqa: BLE001  the task's own failure, handed to on_error (which may re-raise)
            if on_error is None:
                raise
            on_error(key, exc)
            return
        handle(key, result)

    if executor is None:
        for key, args in items:
            settle(key, lambda: task(*args))
            if on_tick:
                on_tick()
        return
    if hasattr(executor, "gather"):  # a dask Client
        from distributed import wait as wait_any  # heavy: imported where used
    else:
        wait_any = futures_wait
    items = iter(items)
    in_flight = {}
    for key, args in itertools.islice(items, max(window, 1)):
        in_flight[executor.submit(task, *args)] = key
    while in_flight:
        for future in wait_any(list(in_flight), return_when="FIRST_COMPLETED").done:
            key = in_flight.pop(future)
            settle(key, future.result)
            following = next(items, None)
            if following is not None:
                in_flight[executor.submit(task, *following[1])] = following[0]
        if on_tick:
            on_tick()


class SharedRing:
    """Shared-memory segments that carry results from pool workers to this process, one per task in flight.

    A block's encoded chunks (tens of MB) went back through the pool's result pipe: pickled, copied
    through a 64 kB pipe under one lock that every worker shares, and unpickled, so a finished worker
    waited for the other's transfer. A worker now writes them into a segment leased for its task
    (:func:`shared_segment`) and returns their offsets; the parent writes from the segment and
    releases it. The segments are this process's: the resource tracker unlinks them if it dies.
    """

    def __init__(self, count: int, size: int):
        from multiprocessing.shared_memory import SharedMemory  # heavy: imported where used (pool runs only)

        self.size = int(size)
        self._segments = {}
        try:
            for _ in range(count):
                segment = SharedMemory(create=True, size=self.size)
                self._segments[segment.name] = segment
        except OSError as exc:
            self.close()
            raise InputError(f"cannot allocate {count} shared-memory segments of {self.size / 2**20:.0f} MiB "
                             f"for the workers' results: {exc.strerror or exc}") from None
        self._free = list(self._segments)
        _reap_tracker_at_exit()

    def lease(self) -> str:
        """A free segment's name, for one task; :meth:`release` returns it."""
        return self._free.pop()

    def release(self, name: str) -> None:
        self._free.append(name)

    def view(self, name: str) -> memoryview:
        return self._segments[name].buf

    def close(self) -> None:
        for segment in self._segments.values():
            try:
                segment.close()
                segment.unlink()
            except (BufferError, FileNotFoundError):  # a view still held, or already gone: the tracker sweeps it
                pass
        self._segments = {}


_ATTACHED: dict = {}
_TRACKER_REAPED_AT_EXIT = False


def _reap_tracker_at_exit() -> None:
    """Stop multiprocessing's resource tracker, and wait for it, as this process exits.

    The segments register with a tracker process of this one's. Left alone it exits a moment after its
    parent, is reparented to PID 1, and where PID 1 reaps nothing (a container's or a micro-VM's init) it
    stays a zombie in the sweep's process group: issue 43 found processes left behind after a default
    sweep. Stopped here, it sweeps whatever was leaked and is reaped by its own parent."""
    global _TRACKER_REAPED_AT_EXIT
    if _TRACKER_REAPED_AT_EXIT:
        return
    _TRACKER_REAPED_AT_EXIT = True

    def stop():
        from multiprocessing import resource_tracker  # heavy: imported where used (a pool run's exit only)

        tracker = getattr(resource_tracker, "_resource_tracker", None)
        with contextlib.suppress(Exception):  # a private interface; without it the tracker ends on its own
            tracker._stop()

    atexit.register(stop)


def shared_segment(name: str) -> memoryview:
    """A worker's view of a :class:`SharedRing` segment, attached once per worker."""
    if name not in _ATTACHED:
        from multiprocessing.shared_memory import SharedMemory  # heavy: imported where used (pool workers)

        _ATTACHED[name] = SharedMemory(name=name)
    return _ATTACHED[name].buf
