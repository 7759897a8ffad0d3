"""How fast this machine runs now, against the machine each cost model was fitted on.

A cost model counts CPU seconds, fitted on one machine in one state; the same work takes another machine, or this
one under other tenants, a different time (the 2-D fault's steps took less CPU on one day than on the day they were
fitted: docs/benchmarks.md, "The machine's speed"). So every estimate is scaled by a **factor**: the CPU time a
fixed reference work takes in this process now, over the time it took where the cost group's constants were
anchored:

    seconds = model seconds x t_ref(now) / t_ref(group)

``data/machine_reference.json`` (``benchmarks/machine_speed.py``) holds t_ref(group) for each cost group: the
reference work's time then, carried to each group by repeating runs of the group's own fit and comparing their CPU
with what the fit recorded. The reference work is numpy's FFT, its transcendental ufuncs and an interpreted loop,
the three kinds of work the models' steps are made of; it runs on this thread only (``time.thread_time``), since an
idle BLAS thread spinning after an import would otherwise charge its time to the work.

The environment variable FAULTSLIP_MACHINE_FACTOR fixes the factor (1: the machine the costs were anchored on);
the tests set it, so that no test depends on the machine's speed.
"""

from __future__ import annotations

import contextlib
import functools
import os
import statistics
import threading
import time

import numpy as np

from faultslip import ranges
from faultslip.errors import InputError
from faultslip.io.resources import read_bundled_table

REFERENCE_FILE = "machine_reference.json"
PRODUCER = "benchmarks/machine_speed.py"
#: The cost groups: each a set of constants fitted together, in one machine state.
GROUPS = ("fault_2d_step", "plane_strain_step", "fault_3d", "families")
#: Repeats of the reference work; the median's thread CPU time is the machine's speed now (each about 1 ms; the
#: median of 5 and of 15 agreed within 3 % in fresh processes).
REPEATS = 7
#: Seconds a probe stands for before the next estimate measures again (a long notebook session outlives a state).
PROBE_LIFETIME = 600.0
ENVIRONMENT = "FAULTSLIP_MACHINE_FACTOR"

_probe: dict = {}
_lock = threading.Lock()


def reference_work(size: int = 4096, rounds: int = 15) -> float:
    """Thread CPU seconds of the fixed reference work: ``rounds`` forward and inverse real FFTs of ``size`` points,
    an exponential, an absolute value and an inverse hyperbolic sine over them, and an interpreted sum of 64
    squares (the kinds of work a model's step does). Deterministic input; nothing is allocated beyond a few
    arrays of ``size``."""
    values = np.cos(np.arange(size) * 0.1)
    start = time.thread_time()
    series = values
    for _ in range(rounds):
        spectrum = np.fft.rfft(series)
        series = np.fft.irfft(spectrum * 0.5, n=size)
        series = np.arcsinh(np.exp(-np.abs(series)) * series) + values
        total = 0.0
        for value in series[:64].tolist():
            total += value * value
    return time.thread_time() - start


def probe_seconds(repeats: int = REPEATS) -> float:
    """The reference work's thread CPU time now: the median of ``repeats`` (after one warm-up)."""
    reference_work()
    return statistics.median(reference_work() for _ in range(repeats))


def reference_now() -> float:
    """This process's measure of :func:`probe_seconds`, taken once and again after :data:`PROBE_LIFETIME`."""
    with _lock:
        now = time.monotonic()
        if not _probe or now - _probe["at"] > PROBE_LIFETIME:
            _probe.update(seconds=probe_seconds(), at=now)
        return _probe["seconds"]


def fixed_factor() -> float | None:
    """The factor FAULTSLIP_MACHINE_FACTOR sets (None where unset); a value that is not a positive number within
    its range is refused in one sentence."""
    text = os.environ.get(ENVIRONMENT)
    if text is None:
        return None
    return ranges.parse_number("machine_factor", text, f"the environment variable {ENVIRONMENT}")


@contextlib.contextmanager
def assumed(value: float):
    """Every factor fixed at ``value`` inside the block, as FAULTSLIP_MACHINE_FACTOR fixes it (a benchmark records
    the anchored estimate, value 1, beside the one it scaled)."""
    saved = os.environ.get(ENVIRONMENT)
    os.environ[ENVIRONMENT] = repr(float(value))
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop(ENVIRONMENT, None)
        else:
            os.environ[ENVIRONMENT] = saved


@functools.lru_cache(maxsize=1)
def references() -> dict:
    """The reference work's anchored time per cost group (s), from ``data/machine_reference.json`` (read once a
    process: every estimate's leaf asks for it, a sweep's cost for each sampled cell)."""
    table = read_bundled_table(REFERENCE_FILE, "the cost models' machine reference", PRODUCER)
    groups = table.get("groups")
    missing = [group for group in GROUPS if not isinstance(groups, dict) or not isinstance(groups.get(group), dict)
               or not float(groups[group].get("reference_work_seconds", 0.0)) > 0.0]
    if missing:
        raise InputError(f"{REFERENCE_FILE} lacks the reference of {', '.join(missing)}; rerun {PRODUCER}")
    return {group: float(groups[group]["reference_work_seconds"]) for group in GROUPS}


def factor(group: str) -> float:
    """How much longer a cost group's work takes on this machine now than its constants say: the reference work's
    time now over its anchored time (FAULTSLIP_MACHINE_FACTOR, where set, instead)."""
    if group not in GROUPS:
        raise ValueError(f"unknown cost group {group!r}; the groups are {', '.join(GROUPS)}")
    fixed = fixed_factor()
    if fixed is not None:
        return fixed
    return reference_now() / references()[group]


def on_this_machine(seconds: float, group: str) -> float:
    """``seconds`` of a cost group's model, as CPU seconds on this machine now (:func:`factor`); 0 stays 0 without
    measuring anything."""
    return seconds * factor(group) if seconds else seconds


def describe() -> str:
    """One sentence for an estimate's report: how the cost models were carried to this machine."""
    fixed = fixed_factor()
    if fixed is not None:
        return f"cost models scaled by {fixed:g}, as {ENVIRONMENT} sets"
    now = reference_now()
    scaled = ", ".join(f"{group} x{now / seconds:.2f}" for group, seconds in references().items())
    return (f"cost models scaled to this machine: its reference work took {now * 1e3:.3g} ms of CPU now "
            f"(faultslip.io.machine), so {scaled}")
