"""Worker processes that die with their parent, and a Ctrl-C that stops everything cleanly.

A worker of :func:`worker_pool` ignores SIGINT (Ctrl-C reaches the whole process group, and only
the parent should answer it: one line, exit 130) and is killed by the kernel when its parent dies,
whatever killed the parent (``kill -9`` included): ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux,
and everywhere a watchdog thread that exits once the parent is gone. :func:`stop_pool` terminates
the workers instead of waiting for their tasks, so an interrupt never waits on, or deadlocks with,
a busy pool.
"""

from __future__ import annotations

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


def usable_workers(requested: int, tasks: int | None = None) -> tuple[int, str]:
    """``(workers, note)``: ``requested`` capped at the cores and the tasks; the note says why, or is ''.

    More processes than cores only add start-up time and memory; more than tasks stay idle.
    """

    if requested < 1:
        raise InputError(f"--workers must be at least 1, got {requested}")
    cores = os.cpu_count() or 1
    limit = min(cores, tasks) if tasks is not None else cores
    limit = max(limit, 1)
    if requested <= limit:
        return requested, ""
    why = f"{cores} cores" if limit == cores else f"{tasks} chunks of work"
    return limit, f"--workers {requested} capped at {limit} ({why}: more would not run faster)"


def _die_with_parent(parent: int) -> None:
    """Worker initializer: ignore Ctrl-C and exit when the parent process is gone."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
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


def run_windowed(executor, task, items, handle, *, window: int, on_tick=None) -> None:
    """Run ``task(*args)`` for each ``(key, args)`` of ``items``; ``handle(key, result)`` in this process.

    ``executor`` is None (in this process, in order), a process pool or a dask Client. At most
    ``window`` tasks are in flight, so memory stays flat however many items there are.
    ``on_tick()`` runs after every handled batch (progress records, periodic flushes).
    """
    if executor is None:
        for key, args in items:
            handle(key, task(*args))
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
            handle(key, future.result())
            following = next(items, None)
            if following is not None:
                in_flight[executor.submit(task, *following[1])] = following[0]
        if on_tick:
            on_tick()
