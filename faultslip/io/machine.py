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

A probe samples a moment, and a moment can mislead: on one 2-core machine, fresh processes read the same work at
0.75-1.29 times its anchored time, one process probing every 0.3 s read 0.78-1.83, while a pool's 2-D steps ran at
0.79-1.17 times their fitted CPU on both workers, whatever each worker's probe had read (0.76 and 1.40). So every
reading is kept in the **machine speed record**, a small JSON file in the user's cache folder
(``$XDG_CACHE_HOME/faultslip/machine_speed.json``, or the path in FAULTSLIP_MACHINE_RECORD; ``off`` keeps none),
and t_ref(now) is the median of the last :data:`RECORD_READINGS` readings of this kind of machine (its processor
model and cores) within :data:`RECORD_MAX_AGE`, this process's included: the long-run speed, which one slow moment
no longer sets. A process's speed follows its own probe in part, so that probe keeps a weight
:data:`PROBE_WEIGHT` beside the median (in logs). The record is read through the io gate (bounded before reading,
never through a link), checked against the checksum written with it, and updated under its lock, atomically; a
record that is damaged, edited or not a regular file is neither used nor overwritten, and the estimate says so in
one warning and uses this process's reading alone.

The environment variable FAULTSLIP_MACHINE_FACTOR fixes the factor (1: the machine the costs were anchored on);
the tests set it, so that no test depends on the machine's speed.
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
import os
import platform
import statistics
import threading
import time
import warnings
from pathlib import Path

import numpy as np

from faultslip import ranges
from faultslip.errors import FaultslipError, InputError
from faultslip.io import gate
from faultslip.io.atomic import write_text_atomic
from faultslip.io.outputs import output_lock, refuse_links
from faultslip.io.processes import usable_cores
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
RECORD_ENVIRONMENT = "FAULTSLIP_MACHINE_RECORD"
#: Readings kept for each kind of machine: the median of 31 follows the machine's long-run speed, and a change of
#: state (a new tenant for hours) moves it within about 16 processes.
RECORD_READINGS = 31
#: Kinds of machine kept in one record (a home folder shared by a cluster's node types), the least recent dropped.
RECORD_MACHINES = 16
#: Seconds a reading stands for: older ones are dropped (a machine's state changes over weeks).
RECORD_MAX_AGE = 30 * 86400.0
#: Bytes of a record read at most: 16 machines of 31 readings are under 40 kB.
RECORD_BYTES = 256 * 1024
#: Seconds to wait for another process's update of the record before going on with this process's reading alone.
RECORD_WAIT = 2.0
RECORD_VERSION = 1
RECORD_LABEL = "machine speed record"
#: The weight of this process's own probe beside the record's median, in logs: ln t_ref = (1 - w) ln median + w ln
#: probe. A process's run speed follows its probe in part: over benchmarks/machine_record.py's 72 processes the least
#: squares slope of ln(run speed / median) on ln(probe / median) was 0.35; a third, tested on a second run of 72 it
#: never saw (slope 0.40 there), spread the estimates over CPU by 0.082 (sd in ln) where the median alone spread
#: them by 0.104 and the probe alone by 0.125 (docs/benchmarks.md, "The machine's speed").
PROBE_WEIGHT = 1.0 / 3.0

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
    """The reference work's time on this machine now: the median of the machine speed record's readings
    (:func:`recorded_median`), this process's :func:`probe_seconds` among them, and that probe weighted
    :data:`PROBE_WEIGHT` beside it in logs; taken once and again after :data:`PROBE_LIFETIME`."""
    with _lock:
        now = time.monotonic()
        if not _probe or now - _probe["at"] > PROBE_LIFETIME:
            reading = probe_seconds()
            median, count, source = recorded_median(reading)
            _probe.update(seconds=median * (reading / median) ** PROBE_WEIGHT, median=median,
                          reading=reading, count=count, source=source, at=now, kept=source == str(record_path()))
        return _probe["seconds"]


def speed_reading() -> dict:
    """How this process read the machine's speed (:func:`reference_now` measures it if it has not): its own probe
    (``reading``, s), the record's median (``median``, s), the ``readings`` that median is of, where they are kept
    (``record``: the record's path, or why none was read), and the time the estimates take (``seconds``)."""
    seconds = reference_now()
    return {"reading": _probe["reading"], "median": _probe["median"], "readings": _probe["count"],
            "record": _probe["source"], "seconds": seconds}


def record_path() -> Path | None:
    """Where the machine speed record lives: FAULTSLIP_MACHINE_RECORD's path (``off`` or empty: none kept), else
    ``$XDG_CACHE_HOME/faultslip/machine_speed.json`` (``~/.cache``)."""
    text = os.environ.get(RECORD_ENVIRONMENT)
    if text is not None:
        return None if text.strip().lower() in ("", "off", "none") else Path(text).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "faultslip" / "machine_speed.json"


@functools.lru_cache(maxsize=1)
def machine_kind() -> str:
    """The record's key for this machine: its processor model and the cores this process may use
    (:func:`faultslip.io.processes.usable_cores`); machines alike share their readings, such as a cluster's nodes
    under one home folder."""
    model = ""
    try:
        for line in gate.read_head("/proc/cpuinfo", "processor description", "table").decode("utf-8", "replace") \
                .splitlines():
            if line.split(":")[0].strip() == "model name":
                model = line.split(":", 1)[1].strip()
                break
    except InputError:  # not Linux
        pass
    model = " ".join((model or platform.processor() or platform.machine() or "unknown processor").split())
    return f"{model[:160]} x{usable_cores()}"


def _damaged(path: Path, why: str) -> InputError:
    return InputError(f"the {RECORD_LABEL} {str(path)!r} {why}; it is neither used nor changed (remove it to start "
                      f"a new one, or set {RECORD_ENVIRONMENT}=off)")


def _reading_ok(reading) -> bool:
    return (isinstance(reading, list) and len(reading) == 2
            and all(isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
                    for value in reading)
            and reading[0] >= 0.0 and 0.0 < reading[1] < 1.0)


def read_record(path) -> dict:
    """The readings of a machine speed record by kind of machine, each a list of [unix time, reference work s]
    ({} where the file does not exist). Read through the gate, at most :data:`RECORD_BYTES` and never through a
    link; one that does not match the checksum written with it, or holds more or other than faultslip writes, is
    refused in one sentence (:class:`InputError`)."""
    path = Path(path)
    refuse_links(path, label=f"the {RECORD_LABEL}")
    if not path.exists():
        return {}
    text = gate.read_text(path, f"the {RECORD_LABEL}", "config", limit=RECORD_BYTES)
    with gate.decoding(path, f"the {RECORD_LABEL}", "JSON"):
        document = json.loads(text)
    if not isinstance(document, dict) or document.get("faultslip_machine_record") != RECORD_VERSION \
            or not isinstance(document.get("machines"), dict):
        raise _damaged(path, "is not a record this faultslip writes")
    if document.get("checksum") != gate.json_checksum(document):
        raise _damaged(path, "does not match the checksum written with it (edited or damaged after writing)")
    machines = document["machines"]
    if len(machines) > RECORD_MACHINES or not all(
            isinstance(readings, list) and 1 <= len(readings) <= RECORD_READINGS and len(kind) <= 200
            and all(_reading_ok(reading) for reading in readings) for kind, readings in machines.items()):
        raise _damaged(path, "holds readings no faultslip writes")
    return machines


def recorded_median(reading: float) -> tuple[float, int, str]:
    """Add this process's ``reading`` (s) to the machine speed record, under its lock; return the median of this
    kind of machine's kept readings, their count and the record's path.

    Where no record is kept, or it cannot be read or written (damaged, a link, a full disk, busy beyond
    :data:`RECORD_WAIT`), the reading stands alone, the count is 1, and a warning says why in one sentence."""
    path = record_path()
    if path is None:
        return reading, 1, f"no record kept ({RECORD_ENVIRONMENT} is off)"
    now, kind = time.time(), machine_kind()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with output_lock(path, "faultslip (machine speed record)", wait=RECORD_WAIT):
            machines = read_record(path)
            kept = [item for item in machines.get(kind, []) if now - item[0] <= RECORD_MAX_AGE]
            kept = (kept + [[now, reading]])[-RECORD_READINGS:]
            machines[kind] = kept
            recent = sorted(machines, key=lambda name: machines[name][-1][0])[-RECORD_MACHINES:]
            document = {"faultslip_machine_record": RECORD_VERSION, "machines": {name: machines[name]
                                                                                 for name in recent}}
            document["checksum"] = gate.json_checksum(document)
            # written under the lock, or a concurrent process's reading is lost
            write_text_atomic(path, json.dumps(document) + "\n", immediate=True)
    except (FaultslipError, OSError) as exc:
        sentence = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        warnings.warn(f"{sentence}; this estimate takes this process's probe of the machine alone", stacklevel=3)
        return reading, 1, f"the {RECORD_LABEL} was not usable"
    return statistics.median(item[1] for item in kept), len(kept), str(path)


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
    count, source = _probe.get("count", 1), _probe.get("source", "")
    where = (f"the median of {count} readings of this kind of machine kept in {source} "
             f"({_probe.get('median', now) * 1e3:.3g} ms) and this process's probe "
             f"({_probe.get('reading', now) * 1e3:.3g} ms), weighted {1 - PROBE_WEIGHT:.2g}:{PROBE_WEIGHT:.2g} in logs"
             if count > 1 else
             f"this process's probe, the first reading kept in {source}" if _probe.get("kept") else
             f"this process's probe alone: {source}" if source else "this process's probe")
    return (f"cost models scaled to this machine: its reference work took {now * 1e3:.3g} ms of CPU, {where} "
            f"(faultslip.io.machine), so {scaled}")
