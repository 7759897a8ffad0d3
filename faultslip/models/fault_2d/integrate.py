"""Earthquake cycles of a 2-D fault: adaptive Dormand-Prince 5(4) stepping, recording, restart.

The state is (slip, psi) on every element. The step's error is the embedded 4th-order estimate,
measured on both, element by element, against ``rtol`` times max(|y|, scale) with the scale D_c
for slip and 1 for psi (the infinity norm), and the step adapts from years between events to
milliseconds within them without a restart (Hairer, Norsett & Wanner, Solving ODEs I, II.4), by a
controller with memory (:func:`next_step_factor`), which holds the step steady where stability, not
accuracy, bounds it.

Recording follows SCEC SEAS BP1 (Erickson et al. 2020): at every step, the stations' slip,
log10 slip rate, shear stress and log10 state; slip profiles every ``profile_interval`` between
events and every ``coseismic_interval`` within them; and an event catalogue, an event being the
time the peak slip rate on the fault exceeds ``event_speed`` (1e-3 m/s).

A run given a ``folder`` streams its records to files there and writes a checkpoint (every
``checkpoint_every`` seconds of computing, atomically). ``resume=True`` continues from the last
checkpoint: the state, the step size and the controller's memory, the stage derivative kept by the pair's first-same-as-last
property and the force balance's warm start are all restored, so the continued run is
bit-identical to one never stopped.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import time as clock
from dataclasses import dataclass, field
from pathlib import Path

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip.models.fault_2d import compiled as compiled_kernels, cost
from faultslip.models.fault_2d.kernel import StressKernel
from faultslip.models.fault_2d import plane_strain
from faultslip.models.fault_2d.model import NEWTON_ITERATIONS, Fault2D, ForceBalance, newton_tolerance
from faultslip.dynamics.shared.dormand_prince import (A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62,
                                                      A63, A64, A65, B1, B3, B4, B5, B6, E1, E3, E4, E5, E6, E7)
from faultslip.errors import InputError, SolverError
from faultslip.io.progress import reporter
from faultslip.io.records import RecordStream, read_checkpoint, write_checkpoint

YEAR = JULIAN_YEAR
#: The SEAS BP1 stations' depths (m).
BP1_STATIONS = (0.0, 2500.0, 5000.0, 7500.0, 10000.0, 12500.0, 15000.0, 17500.0, 20000.0, 25000.0, 30000.0,
                35000.0)
#: Peak slip rate that starts and ends an event (SEAS convention).
EVENT_SPEED = 1e-3
#: The checkpoint's layout; a checkpoint of another version is refused, never misread.
CHECKPOINT_VERSION = 2
#: The step controller's memory weight beta (Hairer, Norsett & Wanner, Solving ODEs I, II.4, eq. 4.13; Hairer &
#: Wanner, Solving ODEs II, IV.2, eq. 2.43'): h_new = h 0.9 err^-(1/5 - 3 beta / 4) err_old^beta, at loose
#: tolerances (rtol >= LOOSE_RTOL) and at tight ones. Between events the step is held by the explicit pair's
#: stability, not its accuracy, and the one-term controller (beta = 0) overshoots there and is rejected again and
#: again; the more so, the looser the tolerance. Trials on SEAS BP1 (512 elements, 300 yr) for beta 0 / 0.04 /
#: 0.08: rtol 1e-3: 3892 / 3441 / 2899; 1e-4: 3879 / 3482 / 3331; 1e-6: 6096 / 5877 / 6232; 1e-8: 12544 / 12487 /
#: 14516 (at tight tolerances the steps are held by accuracy, and a heavy memory makes them sluggish).
STEP_MEMORY = {"loose": 0.08, "tight": 0.04}
LOOSE_RTOL = 1e-4
STATION_FIELDS = ("slip", "log10_slip_rate", "shear_stress", "log10_state")
#: The record streams a run with a folder appends to, in the checkpoint's order.
STREAM_FILES = ("stations.f8", "profiles.f8", "events.f8")
_C2, _C3, _C4, _C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
#: Each trial state of a step as (row of k it is evaluated into, fraction of h, rows of k and their weights):
#: k2..k6, then y_new (row 6, k7), in numpy's order of terms; and the error estimate's.
_STAGES = ((1, _C2, (0,), (A21,)), (2, _C3, (0, 1), (A31, A32)), (3, _C4, (0, 1, 2), (A41, A42, A43)),
           (4, _C5, (0, 1, 2, 3), (A51, A52, A53, A54)), (5, 1.0, (0, 1, 2, 3, 4), (A61, A62, A63, A64, A65)),
           (6, 1.0, (0, 2, 3, 4, 5), (B1, B3, B4, B5, B6)))
_ERROR = ((0, 2, 3, 4, 5, 6), (E1, E3, E4, E5, E6, E7))


@dataclass
class Fault2DRun:
    """What a run recorded (SI units; stations and profiles as arrays over time)."""

    fault: Fault2D
    station_depths: np.ndarray
    station_time: np.ndarray  # (steps + 1,)
    stations: dict  # field -> (steps + 1, stations): an array, or RecordColumns read from the run's folder
    profile_time: np.ndarray
    profile_max_speed: np.ndarray
    profiles: np.ndarray  # (profiles, elements): slip (an array, or RecordColumns)
    profile_log10_slip_rate: np.ndarray  # (profiles, elements) (an array, or RecordColumns)
    events: dict  # start, end, hypocentre_depth, peak_speed (arrays), slip (events, elements)
    steps: int
    rejected: int
    function_evaluations: int
    wall_time: float
    duration: float
    rtol: float
    kernel: str
    final_slip: np.ndarray
    final_state: np.ndarray
    final_time: float
    min_step: float
    max_step: float
    resumed_from: float | None = None
    notes: list = field(default_factory=list)
    #: plane strain only: "normal_stress" at the stations (steps + 1, stations), and at the "surface_positions"
    #: (m) the "surface_displacement" and "surface_velocity" (steps + 1, 2, positions: u then w, w positive down),
    #: in the fault's own sense (a normal fault's are negated on output)
    plane_strain: dict = field(default_factory=dict)

    @property
    def event_count(self) -> int:
        return int(self.events["start"].size)

    def moments_per_length(self) -> np.ndarray:
        """Seismic moment per metre along strike of each event, G times the slip integrated in depth (N)."""
        return self.fault.shear_modulus * self.events["slip"].sum(axis=1) * self.fault.element_size


class _Stations:
    """Linear interpolation between element centres; a depth beyond the first or last centre takes it."""

    def __init__(self, depths, fault: Fault2D):
        self.depths = np.asarray(depths, float)
        if np.any(self.depths < 0) or np.any(self.depths > fault.width):
            raise InputError(f"station depths must lie on the fault, from 0 to {fault.width:g} m")
        centres = fault.depth
        position = np.clip((self.depths - centres[0]) / fault.element_size, 0.0, fault.count - 1.0)
        self.lower = np.minimum(np.floor(position).astype(int), fault.count - 2)
        self.weight = position - self.lower

        #: the elements either side of each station, lower ones first: a record needs its fields there only
        self.neighbours = np.concatenate([self.lower, self.lower + 1])
        #: each neighbour's weight, (2, stations), in :attr:`neighbours`' order
        self.weights = np.stack([1.0 - self.weight, self.weight])

    def __call__(self, values: np.ndarray) -> np.ndarray:
        return self.between(values[self.neighbours])

    def between(self, at_neighbours: np.ndarray) -> np.ndarray:
        """The stations' values from a field's values at :attr:`neighbours`."""
        size = self.lower.size
        return at_neighbours[:size] * self.weights[0] + at_neighbours[size:] * self.weights[1]


def step_memory(rtol: float) -> float:
    """The controller's memory weight beta for ``rtol`` (:data:`STEP_MEMORY`)."""
    return STEP_MEMORY["loose" if rtol >= LOOSE_RTOL else "tight"]


def next_step_factor(norm: float, previous_norm: float, after_rejection: bool, rtol: float) -> float:
    """The factor on h after an accepted step of error ``norm`` (<= 1): the PI controller with the memory weight
    :data:`STEP_MEMORY` for ``rtol``, safety 0.9, between 0.1 and 5, and no growth right after a rejection
    (Hairer's DOPRI5): :func:`faultslip.models.fault_2d.compiled.step_factor`, which the compiled loop takes too."""
    return compiled_kernels.step_factor(norm, previous_norm, after_rejection, step_memory(rtol))


def dormand_prince_trial(derivative, t, y, h, k1, rtol, scale):
    """(y_new, k7, speed and stress at y_new, error norm) of one Dormand-Prince 5(4) trial step in numpy;
    ``derivative(t, y)`` returns (dy/dt, speed, stress). The reference :class:`_CompiledTrial` equals bit for bit.
    A trial far too long (a first step of 1 s into a fast start) may overflow: its norm is then inf or NaN, which
    :func:`~faultslip.models.fault_2d.compiled.judged_step` rejects, shortening the step, as the compiled trial's."""
    with np.errstate(over="ignore", invalid="ignore"):
        k2 = derivative(t + _C2 * h, y + h * (A21 * k1))[0]
        k3 = derivative(t + _C3 * h, y + h * (A31 * k1 + A32 * k2))[0]
        k4 = derivative(t + _C4 * h, y + h * (A41 * k1 + A42 * k2 + A43 * k3))[0]
        k5 = derivative(t + _C5 * h, y + h * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4))[0]
        k6 = derivative(t + h, y + h * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5))[0]
        y_new = y + h * (B1 * k1 + B3 * k3 + B4 * k4 + B5 * k5 + B6 * k6)
        k7, speed_new, stress_new = derivative(t + h, y_new)
        error = h * (E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7)
        return y_new, k7, speed_new, stress_new, float(np.max(np.abs(error) / (
            rtol * np.maximum(np.maximum(np.abs(y), np.abs(y_new)), scale))))


class _CompiledTrial:
    """One Dormand-Prince trial step with its element-wise work in numba's kernels: each stage's state and the
    slip deficit in one pass, the stress and the force balance in one, the error norm in one; the FFTs and the
    spectrum's product stay scipy's and numpy's. The same operations as :func:`run_cycles`'s numpy trial, so the same
    bits, on one thread or several."""

    def __init__(self, fault, operator, balance, scale, rtol, threads):
        self.fault, self.operator, self.balance = fault, operator, balance
        self.kernels = compiled_kernels.kernels(True, threads)
        if threads > 1:
            import numba  # heavy: optional dependency (faultslip[fast]), present whenever this class is used

            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        count = fault.count
        self.count, self.scale, self.rtol = count, scale, rtol
        # each array from a cache line's start, so that the threaded step's parts keep lines of their own
        # (compiled._part_start)
        lines = compiled_kernels.on_lines
        self.stages = lines((7, 2 * count))  # k1 .. k7
        self.work = lines(2 * count)
        self.ratios = lines(2 * count)
        self.stress = lines(count)
        self.plan = [(row, fraction, np.array(rows, dtype=np.int64), np.array(weights, dtype=float))
                     for row, fraction, rows, weights in _STAGES]
        self.error_rows, self.error_weights = np.array(_ERROR[0], dtype=np.int64), np.array(_ERROR[1], dtype=float)

    def _evaluate(self, row: int, state: np.ndarray) -> None:
        """k[row] = f(state), the slip deficit already in the kernel's buffer; the stress kept in self.stress."""
        fault, balance, count = self.fault, self.balance, self.count
        product = self.operator.product_of_padded()
        self.kernels["balance_rates"](product, fault.initial_shear_stress, True, self.stress, state[count:], balance.u,
                                      balance.sigma_a, balance.inverse_a, balance.two_v0_eta, 1.0 / balance.damping,
                                      balance.aging, balance.aging_rate, fault.reference_friction, balance.inverse_b,
                                      fault.reference_speed, fault.critical_slip, fault.b, self.stages[row, :count],
                                      self.stages[row, count:], NEWTON_ITERATIONS, balance.tolerance)

    def __call__(self, t, y, h, k1):
        if self.balance.u is None:  # a resumed run without a warm start: the numpy balance sets one, as at t = 0
            self.balance.rates(t, y[:self.count], y[self.count:])
        stages, stage, padded = self.stages, self.kernels["stage"], self.operator.padded
        stages[0] = k1
        plate_rate = self.fault.plate_rate
        for row, fraction, rows, weights in self.plan:
            target = self.work if row < 6 else np.empty_like(y)
            stage(target, padded, y, h, weights, rows, stages, self.count, plate_rate, t + fraction * h)
            self._evaluate(row, target)
        self.kernels["error_ratios"](self.ratios, y, target, h, self.error_weights, self.error_rows, stages, self.rtol,
                                     self.scale)
        return target, stages[6].copy(), stages[6, :self.count].copy(), self.stress.copy(), float(self.ratios.max())


class _FusedTrial(_CompiledTrial):
    """The whole trial step in one compiled call (:func:`faultslip.models.fault_2d.compiled._fused_step`): the FFTs
    too, through rocket-fft, and no Python between the stages. The same operations as :class:`_CompiledTrial` but
    for K x (its two halves of the spectrum by rocket-fft's DUCC0, :func:`faultslip.models.fault_2d.kernel.
    spectrum_halves`, against one real FFT by scipy's pocketfft): equal to it to round-off, and bit for bit on any
    number of threads."""

    def __init__(self, fault, operator, balance, scale, rtol, threads):
        super().__init__(fault, operator, balance, scale, rtol, threads)
        terms = max(len(rows) for _, _, rows, _ in _STAGES)
        self.plan_rows = np.zeros((len(_STAGES), terms), dtype=np.int64)
        self.plan_weights = np.zeros((len(_STAGES), terms))
        for s, (_, _, rows, weights) in enumerate(_STAGES):
            self.plan_rows[s, :len(rows)], self.plan_weights[s, :len(weights)] = rows, weights
        self.plan_terms = np.array([len(rows) for _, _, rows, _ in _STAGES], dtype=np.int64)
        self.plan_fractions = np.array([fraction for _, fraction, _, _ in _STAGES])
        halves = operator.halves  # K x in two halves of its spectrum, one a task (kernel.spectrum_halves)
        self.halves = halves.table
        lines = compiled_kernels.on_lines
        self.padded = lines(halves.half_length)  # the slip deficit, zero beyond the elements
        self.transforms = lines((4, halves.half_length // 2 + 1), complex)
        self.even_product = lines(halves.half_length)
        self.product = lines(self.count)
        self.coefficients, self.healing, self.u_start = (lines(self.count) for _ in range(3))
        self.warm = lines((compiled_kernels.WARM_ROWS, self.count))
        self.partial = lines(2 * self.count)
        self.sync = compiled_kernels.new_sync()
        self.part_extremes = lines((2, compiled_kernels.PARALLEL_PARTS))  # compiled.LARGEST_RATIO, PEAK_SPEED
        self.tasks = threads  # one task a thread: at most the threads numba has (checked at each step)

    def __call__(self, t, y, h, k1):
        if self.balance.u is None:  # a resumed run without a warm start: the numpy balance sets one, as at t = 0
            self.balance.rates(t, y[:self.count], y[self.count:])
        fault, balance, stages = self.fault, self.balance, self.stages
        stages[0] = k1
        y_new = compiled_kernels.on_lines(y.shape)
        balance.u = compiled_kernels.lined(balance.u)  # the solves write it a part at a time
        norm = self.kernels["fused_step"](
            y, h, t, stages, self.work, self.partial, y_new, self.padded, self.transforms, self.even_product,
            self.product, self.coefficients, self.healing, self.warm, self.halves, fault.initial_shear_stress, self.stress, balance.u, self.u_start, balance.sigma_a, balance.inverse_a,
            balance.two_v0_eta, 1.0 / balance.damping, balance.aging, balance.aging_rate, fault.reference_friction,
            balance.inverse_b, fault.reference_speed, fault.critical_slip, fault.b, NEWTON_ITERATIONS,
            balance.tolerance, self.plan_rows, self.plan_weights, self.plan_terms, self.plan_fractions,
            self.error_rows, self.error_weights, self.rtol, self.scale, self.ratios, fault.plate_rate, self.sync,
            self.part_extremes, self._tasks())
        return y_new, stages[6].copy(), stages[6, :self.count].copy(), self.stress.copy(), float(norm)

    def _tasks(self) -> int:
        """The threaded step's tasks, one a thread: never more than numba's threads for this caller, else a task
        would wait at a barrier for one that never starts."""
        if self.tasks == 1:
            return 1
        import numba  # heavy: optional dependency (faultslip[fast]), present whenever this class is used

        return min(self.tasks, numba.get_num_threads())


#: an automatic run's probe: this many trial steps on each of its threads and one thread, interleaved
PROBE_STEPS = 8
#: seconds of the faster before the next probe after one that changed the choice (the machine's other work comes
#: and goes, and a virtual machine's vCPUs move: on the benchmark machine their placement changed within a
#: second, a stretch lasting 0.26 s, median); each probe that keeps the choice doubles the wait, up to LONGEST_HOLD
PROBE_EVERY = 0.1
LONGEST_HOLD = 30.0


class _FasterTrial:
    """The faster of a run's threaded trial step and its one-thread one, timed on the run's own steps.

    On a machine whose other work holds a core, the threads' barriers wait for the thread that shares it, and two
    threads run slower than one: BP1 at 1,600 elements over 300 years took 5.4-8.7 s on two threads against
    2.5 s on one, with a busy loop on the second of two cores; and on a virtual machine whose two vCPUs the host
    moves between near and far, two threads gain 1.4-1.6x near and lose far, changing within a second. So an
    automatic run times :data:`PROBE_STEPS` steps of each, interleaved, takes the one with the smaller total, and
    probes again after a wait: :data:`PROBE_EVERY` seconds after a probe that changed the choice, twice the last
    wait after one that kept it, at most :data:`LONGEST_HOLD` (a steady machine is probed seldom, a changing one
    often). Both give the same bits (tested), so the choice changes no number. ``steps`` counts the trial steps
    each took (threaded, one thread)."""

    def __init__(self, threaded, single, timer=clock.perf_counter):
        self.trials, self.timer = (threaded, single), timer
        self.times = ([], [])
        self.steps = [0, 0]
        self.choice = None  # None while probing, else the index of the faster
        self.last_choice = None
        self.turn = 0
        self.next_probe = 0.0
        self.hold = PROBE_EVERY

    def __call__(self, t, y, h, k1):
        which, probe = self.choose()
        if not probe:
            self.steps[which] += 1
            return self.trials[which](t, y, h, k1)
        start = self.timer()
        result = self.trials[which](t, y, h, k1)
        self.timed(which, start, self.timer())
        return result

    def choose(self) -> tuple:
        """(the index of the trial to take next, whether it is a probe's, to be timed by :meth:`timed`)."""
        if self.choice is not None and self.timer() < self.next_probe:
            return self.choice, False
        if self.choice is not None:  # time for a new probe
            self.choice, self.times = None, ([], [])
        which, self.turn = self.turn, 1 - self.turn
        return which, True

    def trials_until_probe(self) -> int:
        """The chosen trial's steps that fit before the next probe at its probe's pace (at least one): a caller
        taking many steps a call returns in time for it."""
        times = self.times[self.choice]
        pace = sum(times) / len(times)
        return max(1, int((self.next_probe - self.timer()) / pace)) if pace > 0 else 1

    def timed(self, which: int, start: float, end: float) -> None:
        """A probe's trial step ``which`` took from ``start`` to ``end``: the choice once both have
        :data:`PROBE_STEPS`."""
        if self.steps[which]:  # a first call loads (or compiles) its kernels: not a step's time
            self.times[which].append(end - start)
        self.steps[which] += 1
        if min(len(self.times[0]), len(self.times[1])) >= PROBE_STEPS:
            # the total, not the median: a busy core stalls few steps, but each by a time slice of milliseconds
            self.choice = int(sum(self.times[1]) < sum(self.times[0]))
            kept = self.choice == self.last_choice
            self.hold = min(2.0 * self.hold, LONGEST_HOLD) if kept else PROBE_EVERY
            self.last_choice = self.choice
            self.next_probe = end + self.hold


class _CompiledSteps:
    """Many steps a call (:func:`faultslip.models.fault_2d.compiled._run_steps`) on a :class:`_FusedTrial`'s
    buffers: the integrator's loop in compiled code, returning to :func:`run_cycles` only where it has something
    to do. ``chooser`` (a run whose threads were chosen for it): each call takes the trial's threads or one, as a
    :class:`_FasterTrial` over the two picks (a probe's call takes one trial step, timed)."""

    #: station records a call can buffer; trials a call takes at most (its next return checks the checkpoint's
    #: and the progress bar's clocks); the bytes of profile rows a call can buffer (at most PROFILES rows, at least 1)
    RECORDS = 512
    TRIALS = 512
    PROFILES, PROFILE_BYTES = 64, 1 << 22

    def __init__(self, trial: _FusedTrial, near: np.ndarray, settings: dict, chooser: _FasterTrial | None = None):
        count = trial.count
        self.trial, self.near, self.chooser = trial, near, chooser
        self.kernel = trial.kernels["run_steps"]
        self.states = compiled_kernels.on_lines((2, 2 * count))  # a row a state, each on cache lines
        self.clock = np.zeros(compiled_kernels.CLOCK_SLOTS)
        self.counters = np.zeros(compiled_kernels.COUNTER_SLOTS, dtype=np.int64)
        self.settings = np.zeros(compiled_kernels.SETTINGS_SLOTS)
        for slot, name in ((compiled_kernels.DURATION, "duration"), (compiled_kernels.RTOL, "rtol"),
                           (compiled_kernels.MEMORY_WEIGHT, "memory_weight"),
                           (compiled_kernels.EVENT_LIMIT, "event_speed"),
                           (compiled_kernels.PROFILE_INTERVAL, "profile_interval"),
                           (compiled_kernels.COSEISMIC_INTERVAL, "coseismic_interval")):
            self.settings[slot] = settings[name]
        self.records = np.empty((self.RECORDS, 1 + 4 * near.size))
        # a profile row: t, the peak slip rate, and every element's slip and slip rate (compiled._record_profile)
        self.profiles = np.empty((max(1, min(self.PROFILES, self.PROFILE_BYTES // (8 * (2 + 2 * count)))),
                                  2 + 2 * count))

    def __call__(self, budget: int) -> None:
        """Steps until :func:`_run_steps` returns, at most ``budget`` trials (the state in, and out, through
        :attr:`states`, :attr:`clock` and :attr:`counters`)."""
        chooser, trial = self.chooser, self.trial
        which, probe = chooser.choose() if chooser is not None else (0, False)
        tasks = trial._tasks() if which == 0 else 1
        if probe:
            budget = 1
        elif chooser is not None:
            budget = min(budget, chooser.trials_until_probe())
        self.counters[compiled_kernels.BUDGET] = min(budget, self.TRIALS)
        fault, balance = trial.fault, trial.balance
        balance.u = compiled_kernels.lined(balance.u)  # the solves write it a part at a time
        start, evaluations = clock.perf_counter(), int(self.counters[compiled_kernels.EVALUATIONS])
        self.kernel(
            self.states, self.clock, self.counters, self.settings, self.records, self.near, self.profiles,
            trial.stages, trial.work,
            trial.partial, trial.padded, trial.transforms, trial.even_product, trial.product, trial.coefficients,
            trial.healing, trial.warm, trial.halves, fault.initial_shear_stress, trial.stress, balance.u,
            trial.u_start, balance.sigma_a, balance.inverse_a, balance.two_v0_eta, 1.0 / balance.damping,
            balance.aging, balance.aging_rate, fault.reference_friction, balance.inverse_b, fault.reference_speed,
            fault.critical_slip, fault.b, NEWTON_ITERATIONS, balance.tolerance, trial.plan_rows, trial.plan_weights,
            trial.plan_terms, trial.plan_fractions, trial.error_rows, trial.error_weights, trial.scale, trial.ratios,
            fault.plate_rate, trial.sync, trial.part_extremes, tasks)
        if chooser is not None:
            if probe:
                chooser.timed(which, start, clock.perf_counter())
            else:
                chooser.steps[which] += (int(self.counters[compiled_kernels.EVALUATIONS]) - evaluations) // 6


def threads_offered(threads: int) -> int:
    """The threads numba offers this process, at most ``threads``. numba counts the cores the process may use
    when it is first imported, once: a process held to one core then (a ``taskset`` or ``os.sched_setaffinity``
    before its first compiled run) has one thread for the rest of its life, whatever it may use later."""
    import numba  # heavy: optional dependency (faultslip[fast]), present wherever the compiled kernels are

    return max(1, min(threads, numba.config.NUMBA_NUM_THREADS))


def step_path() -> str:
    """The path this process's steps take (:data:`kernel.STEP_PATHS`), which decides the dense/FFT crossover."""
    if not compiled_kernels.available():
        return "numpy"
    return "fused" if compiled_kernels.fused_available() else "compiled"


def first_run_cost(fused: bool, threads: int, fresh_process: bool = False) -> tuple[float, str]:
    """CPU seconds a run in this process (``fresh_process``: in a new one, a study's worker) spends before its first
    step, and on what (:func:`faultslip.models.fault_2d.cost.fault_2d_first_run`): loading the compiled step
    (``fused``: the whole step's; else the force balance's) for ``threads`` threads, or compiling it where numba's
    cache has none; nothing where the process holds it already, or where the step is plain numpy."""
    if step_path() == "numpy" or (not fresh_process and compiled_kernels.step_loaded(threads, fused)):
        return 0.0, ""
    return cost.fault_2d_first_run(fused=fused, threads=threads,
                                   compile=compiled_kernels.compilation_pending(threads, fused))


def _compiled_trial(fault, operator, balance, scale, rtol, threads):
    """The whole step compiled where it can be (an FFT kernel, and rocket-fft here), else its element-wise work."""
    if operator.method == "fft" and compiled_kernels.fused_available():
        return _FusedTrial(fault, operator, balance, scale, rtol, threads)
    return _CompiledTrial(fault, operator, balance, scale, rtol, threads)


def fingerprint(fault: Fault2D, settings: dict) -> str:
    """A digest of everything that decides a run's numbers: a checkpoint of another run is refused."""
    digest = hashlib.sha256()
    for key in ("a", "b", "critical_slip", "normal_stress", "initial_shear_stress", "initial_state"):
        digest.update(np.ascontiguousarray(getattr(fault, key)).tobytes())
    scalars = {key: getattr(fault, key) for key in ("element_size", "shear_modulus", "shear_wave_speed", "plate_rate",
                                                   "reference_speed", "reference_friction", "evolution")}
    if fault.plane != "antiplane":  # an antiplane run's digest stays what it was
        scalars.update({key: getattr(fault, key) for key in ("plane", "dip", "sense", "poisson_ratio")})
    digest.update(json.dumps({**scalars, **settings}, sort_keys=True, default=repr).encode())
    return digest.hexdigest()


def run_cycles(fault: Fault2D, duration: float, *, rtol: float = 1e-8, stations=BP1_STATIONS, kernel: str = "auto",
               profile_interval: float = 5 * YEAR, coseismic_interval: float = 1.0, event_speed: float = EVENT_SPEED,
               folder=None, resume: bool = False, checkpoint_every: float = 60.0, max_steps: int = 20_000_000,
               stop_after_steps: int | None = None, progress=None, initial_step: float = 1.0,
               threads: int = 1, adapt_threads: bool = False, time_limit: float | None = None,
               surface_stations=plane_strain.BP3_SURFACE_STATIONS, operator=None) -> Fault2DRun:
    """Integrate ``fault`` from t = 0 to ``duration`` (s) and record stations, profiles and events.

    With numba, each step's element-wise work runs in compiled kernels (:mod:`faultslip.models.fault_2d.compiled`)
    over ``threads`` threads; the numbers are the same on any number of threads. With ``adapt_threads`` (a run
    whose threads were chosen for it) the run times its steps on ``threads`` threads and on one and takes the
    faster, again every half minute (:class:`_FasterTrial`): on a busy machine one thread can be the faster.

    ``folder``: stream records and checkpoints there (a run can then be resumed). ``stop_after_steps``
    stops as a kill would, right after a checkpoint at that step (for tests of restart).
    ``progress``: True for a bar, or a callable (done, total) in years (:mod:`faultslip.io.progress`).
    ``time_limit``: wall seconds after which the run checkpoints (with a folder) and stops, raising
    :class:`OverBudget` (an estimate can be far off: nothing else would stop a run once its budget is spent).
    ``surface_stations``: a plane-strain fault's surface positions (m from the trace, + over the hanging wall),
    whose displacement and velocity are recorded at every step with the normal stress at the stations.

    A plane-strain fault (``fault.plane == "strain"``) takes the dense traction kernels of
    :mod:`faultslip.models.fault_2d.plane_strain` and the same stepping, records and checkpoints.

    ``operator``: the traction operator of a fault the 2-D kernels do not describe (the 3-D fault's FFT along
    strike): ``operator(deficit)`` the shear stress change, ``both(deficit)`` that and the normal one stacked where
    ``operator.normal_changes``, ``operator.method`` its name and ``operator.settings`` what decides its numbers
    (for the checkpoint's digest). ``stations`` may then be a recorder of the fault's own (``depths``,
    ``neighbours``, ``weights``: each station a weighted sum of its neighbours' values). The stepping, records,
    events and checkpoints are this function's.
    """
    if not (duration > 0 and math.isfinite(duration)):
        raise InputError(f"the duration must be a positive time, got {duration!r}")
    if not 1e-14 <= rtol <= 1e-2:
        raise InputError(f"rtol must lie between 1e-14 and 1e-2, got {rtol!r}")
    if not (profile_interval > 0 and coseismic_interval > 0 and event_speed > 0):
        raise InputError("the profile intervals and the event speed must be positive")
    if not (isinstance(threads, int) and 1 <= threads <= 1024):
        raise InputError(f"threads must be a whole number from 1 to 1024, got {threads!r}")
    strain = fault.plane == "strain" and operator is None
    if operator is not None:
        if kernel not in ("auto", operator.method):
            raise InputError(f"this fault's stress comes from its own operator ({operator.method}), got kernel "
                             f"{kernel!r}")
        balance = (plane_strain.PlaneStrainBalance(fault, operator) if getattr(operator, "normal_changes", False)
                   else ForceBalance(fault, operator))
    elif strain:
        if kernel not in ("auto", "dense"):
            raise InputError(f"a plane-strain fault's kernel is dense (its free surface and dip break the "
                             f"antiplane kernel's convolution), got {kernel!r}")
        operator = plane_strain.PlaneStrainOperator(fault)
        balance = plane_strain.PlaneStrainBalance(fault, operator)
        surface_positions = np.asarray(surface_stations, float)
        surface = plane_strain.surface_kernel(surface_positions, fault.count, fault.element_size, fault.dip,
                                              fault.shear_modulus, fault.poisson_ratio).reshape(-1, fault.count)
    else:
        operator = StressKernel(fault.count, fault.element_size, fault.shear_modulus, kernel, path=step_path())
        balance = ForceBalance(fault, operator)
    balance.tolerance = newton_tolerance(rtol)
    recorder = stations if hasattr(stations, "neighbours") else _Stations(stations, fault)
    settings = {"duration": duration, "rtol": rtol, "stations": [float(d) for d in recorder.depths],
                "profile_interval": profile_interval, "coseismic_interval": coseismic_interval,
                "event_speed": event_speed, "kernel": operator.method}
    if hasattr(operator, "settings"):
        settings["operator"] = operator.settings
        settings["station_elements"] = [int(i) for i in recorder.neighbours]
    if strain:
        settings["surface_stations"] = [float(x) for x in surface_positions]
    digest = fingerprint(fault, settings)
    folder = Path(folder) if folder is not None else None
    count = fault.count
    station_width = 1 + len(STATION_FIELDS) * recorder.depths.size
    widths = (station_width, 2 * count + 2, count + 5)  # stations, profiles, events: the rows of STREAM_FILES
    stream_files = STREAM_FILES
    if strain:  # the normal stress at the stations, and the surface's displacement and velocity, every step
        stream_files = STREAM_FILES + ("plane_strain.f8",)
        widths = widths + (1 + recorder.depths.size + 4 * surface_positions.size,)
    checkpoint = folder / "checkpoint.npz" if folder is not None else None
    scale = np.concatenate([fault.critical_slip, np.ones(count)])
    theta_offset = np.log10(fault.critical_slip / fault.reference_speed)
    inverse_b_ln10 = np.where(fault.b > 0, 1.0 / (np.where(fault.b > 0, fault.b, 1.0) * math.log(10.0)), 0.0)

    def derivative(t, y):
        speed, psi_rate, stress = balance.rates(t, y[:count], y[count:])
        return np.concatenate([speed, psi_rate]), speed, stress

    def numpy_trial(t, y, h, k1):
        return dormand_prince_trial(derivative, t, y, h, k1, rtol, scale)

    notes = []
    offered = threads_offered(threads) if balance.compiled and threads > 1 else threads
    if offered < threads:
        notes.append(f"{threads} threads were asked for and numba offers this process {offered}: it counted the "
                     f"cores the process could use when numba was first imported, and the process was held to fewer "
                     f"then; the run took {offered} (start the process on the cores it should use)")
    choose_threads = adapt_threads and threads > 1
    if not balance.compiled or strain or hasattr(operator, "settings"):  # a dense or 3-D product: its cost rules
        trial = numpy_trial
    else:
        trial = _compiled_trial(fault, operator, balance, scale, rtol, threads)
        if choose_threads and not isinstance(trial, _FusedTrial):  # a fused trial chooses its threads a call
            trial = _FasterTrial(trial, _compiled_trial(fault, operator, balance, scale, rtol, 1))

    near = recorder.neighbours  # every field at the stations' neighbouring elements only: a step's record is
    theta_offset_near, inverse_b_ln10_near = theta_offset[near], inverse_b_ln10[near]  # then 12 stations' work, not N
    sites = recorder.depths.size
    weights = recorder.weights  # (neighbours per station, stations)
    steps_in_one_call = None
    if isinstance(trial, _FusedTrial):  # the whole step compiled: the loop too, many steps a call
        steps_in_one_call = _CompiledSteps(trial, near, {
            "duration": duration, "rtol": rtol, "memory_weight": step_memory(rtol),
            "event_speed": event_speed, "profile_interval": profile_interval,
            "coseismic_interval": coseismic_interval}, _FasterTrial(None, None) if choose_threads else None)

    def station_rows(raw):
        # records from the raw rows of compiled._record_near (t, then slip, slip rate, stress and state at the
        # neighbours): the four fields and one interpolation over a block of rows, the same operations on each
        # number as recorder.between's, so its bits
        rows, width = raw.shape[0], near.size
        at_neighbours = raw[:, 1:].reshape(rows, len(STATION_FIELDS), width)
        speed_near = at_neighbours[:, 1]
        fields = np.empty((rows, len(STATION_FIELDS), width))
        fields[:, 0] = at_neighbours[:, 0]
        with np.errstate(divide="ignore"):  # a rate of 0 is -inf
            np.log10(speed_near, out=fields[:, 1])
        np.subtract(at_neighbours[:, 2], fault.damping * speed_near, out=fields[:, 2])
        np.multiply(at_neighbours[:, 3] - fault.reference_friction, inverse_b_ln10_near, out=fields[:, 3])
        fields[:, 3] += theta_offset_near
        out = np.empty((rows, 1 + len(STATION_FIELDS) * sites))
        out[:, 0] = raw[:, 0]
        combined = fields[:, :, :sites] * weights[0]
        for k in range(1, len(weights)):  # the same operations, in the same order, as recorder.between
            combined = combined + fields[:, :, k * sites:(k + 1) * sites] * weights[k]
        out[:, 1:].reshape(rows, -1, sites)[:] = combined
        return out

    raw_row = np.empty((1, 1 + len(STATION_FIELDS) * near.size))

    def station_row(t, y, speed, stress):
        # one step's record (a step at a time, the Python loop's): compiled._record_near's raw row, by numpy
        raw_row[0, 0] = t
        for i, values in enumerate((y, speed, stress, y[count:])):
            values.take(near, out=raw_row[0, 1 + i * near.size:1 + (i + 1) * near.size])
        return station_rows(raw_row)[0]

    def profiles_from_raw(raw):
        # profiles from raw rows (t, peak slip rate, slip, slip rate: compiled._record_profile), in place: the
        # rate's log10 over the block
        with np.errstate(divide="ignore"):  # a rate of 0 is -inf
            np.log10(raw[:, 2 + count:], out=raw[:, 2 + count:])
        return raw

    def profile_row(t, y, speed):
        # one step's profile (the Python loop's, and a compiled call's last step)
        return profiles_from_raw(np.concatenate([[t, speed.max()], y[:count], speed])[np.newaxis])[0]

    if strain:
        rigid_rate = plane_strain.rigid_motion(surface_positions, 1.0, fault.plate_rate, fault.dip).ravel()

        def strain_row(t, y, speed):
            # the normal stress at the stations, and the surface's displacement and velocity: K_surface applied to
            # the slip deficit and its rate, plus each side's rigid motion (BP3 eq. 4)
            return np.concatenate([[t], recorder(balance.normal_stress),
                                   surface @ (y[:count] - fault.plate_rate * t) + rigid_rate * t,
                                   surface @ (speed - fault.plate_rate) + rigid_rate])

    resumed_from = None
    if resume:
        if checkpoint is None or not (checkpoint.is_file() or checkpoint.is_symlink()):
            raise InputError(f"nothing to resume: {folder} holds no checkpoint of a 2-D fault run")
        saved = _read_checkpoint(checkpoint, digest, count, len(stream_files))
        t, y, h, k1 = float(saved["t"]), saved["y"].copy(), float(saved["h"]), saved["k1"].copy()
        balance.u = saved["u"].copy() if saved["u"].size else None
        speed, stress = saved["speed"].copy(), saved["stress"].copy()
        steps, rejected, evaluations = (int(v) for v in saved["counters"][:3])
        min_step, max_step, wall_before = (float(v) for v in saved["steps_range"])
        previous_norm, after_rejection = float(saved["controller"][0]), bool(saved["controller"][1])
        event = _event_record(saved["event"], checkpoint)
        event_slip = saved["event_slip"].copy()
        last_profile, last_coseismic = (float(v) for v in saved["profile_times"])
        rows, digests = [int(v) for v in saved["rows"]], [str(v) for v in saved["stream_digests"]]
        streams = [RecordStream(folder / name, width, kept, stream_digest) for name, width, kept, stream_digest
                   in zip(stream_files, widths, rows, digests)]
        stations_store, profiles_store, events_store = streams[:3]
        resumed_from = t
    else:
        if folder is not None:
            folder.mkdir(parents=True, exist_ok=True)
        t, h = 0.0, float(initial_step)
        y = np.concatenate([np.zeros(count), fault.initial_state])
        k1, speed, stress = derivative(t, y)
        if not np.all(np.isfinite(k1)):
            bad = int(np.argmax(~np.isfinite(k1[:count]) | ~np.isfinite(k1[count:])))
            raise InputError(f"{fault.KIND}: the initial stress and state give no finite slip rate at depth "
                             f"{fault.depth[bad]:.4g} m; check [initial] and the friction there")
        steps = rejected = 0
        evaluations = 1
        previous_norm, after_rejection = 1e-4, False  # Hairer's start: no memory of an earlier error
        min_step, max_step, wall_before = math.inf, 0.0, 0.0
        event = {"inside": False, "start": 0.0, "hypocentre": 0.0, "peak": 0.0}
        event_slip = np.zeros(count)
        last_profile, last_coseismic = -math.inf, -math.inf
        streams = [RecordStream(folder / name if folder else None, width) for name, width in zip(stream_files, widths)]
        stations_store, profiles_store, events_store = streams[:3]
        stations_store.append(station_row(t, y, speed, stress))
        if strain:
            streams[3].append(strain_row(t, y, speed))
        profiles_store.append(profile_row(t, y, speed))
        last_profile = t

    def save():
        for stream in streams:
            stream.sync()
        write_checkpoint(checkpoint, version=CHECKPOINT_VERSION, digest=digest, t=t, y=y, h=h, k1=k1,
                         u=balance.u if balance.u is not None else np.empty(0), speed=speed, stress=stress,
                         counters=np.array([steps, rejected, evaluations]),
                         steps_range=np.array([min_step, max_step, wall_before + clock.perf_counter() - started]),
                         controller=np.array([previous_norm, float(after_rejection)]),
                         event=json.dumps(event), event_slip=event_slip,
                         profile_times=np.array([last_profile, last_coseismic]),
                         rows=np.array([stream.rows for stream in streams]),
                         stream_digests=np.array([stream.digest() for stream in streams]))

    def step_budget_spent():
        return SolverError(f"{fault.KIND}: {steps} steps reached the budget at t = {t / YEAR:.6g} yr of "
                           f"{duration / YEAR:.6g}; raise max_steps or loosen rtol")

    def step_collapsed():  # t + h would no longer differ from t
        return SolverError(f"{fault.KIND}: Dormand-Prince's step collapsed to {h:.3g} s at t = {t / YEAR:.6g} yr "
                           f"(peak slip rate {speed.max():.3g} m/s); tighten rtol or refine the elements")

    if balance.compiled and compiled_kernels.compilation_pending(threads):
        notes.append("this run compiled the 2-D step for this environment (numba caches it: later runs load it; "
                     "benchmarks/first_run.py measures the first run against a warm one)")
        if progress is not None and progress is not False:
            announce = getattr(progress, "announce", None) or (lambda text: print(f"faultslip: {text}", file=sys.stderr))
            announce("compiling the 2-D step for this environment, once (numba caches it for later runs)")
    try:
        progress = reporter(progress, fault.KIND, "yr")
        started = clock.perf_counter()
        last_save = last_report = started
        log_threshold = math.log(event_speed)
        peak = float(speed.max())  # the accepted state's, kept: one max a step
        while t < duration:
            if steps_in_one_call is not None:  # many steps in one compiled call, to the next that needs Python
                if balance.u is None:  # a resumed run without a warm start: the numpy balance sets one, as at t = 0
                    balance.rates(t, y[:count], y[count:])
                before = steps
                many = steps_in_one_call
                many.states[0] = y
                many.trial.stages[0] = k1
                many.clock[:] = (t, h, previous_norm, float(after_rejection), min_step, max_step, peak, peak,
                                 event["peak"], t, last_profile, last_coseismic)
                many.counters[[compiled_kernels.STEPS, compiled_kernels.REJECTED, compiled_kernels.EVALUATIONS,
                               compiled_kernels.CURRENT, compiled_kernels.STOP_AT, compiled_kernels.MAX_STEPS,
                               compiled_kernels.PROFILE_ROWS]] = (
                    steps, rejected, evaluations, 0, -1 if stop_after_steps is None else stop_after_steps,
                    max_steps, 0)
                many.settings[compiled_kernels.INSIDE] = float(event["inside"])
                many(many.TRIALS)
                (t, h, previous_norm, after_rejection, min_step, max_step, peak, previous_peak, event_peak,
                 t_old, last_profile, last_coseismic) = (float(value) for value in many.clock)
                after_rejection = after_rejection != 0.0
                steps, rejected, evaluations, rows, current, _, _, _, returned, profiles_taken = (
                    int(v) for v in many.counters)
                y, k1, stress = many.states[current], many.trial.stages[0], many.trial.stress
                speed = k1[:count]
                if rows:
                    stations_store.extend(station_rows(many.records[:rows]))
                if profiles_taken:  # the profiles the call took
                    profiles_store.extend(profiles_from_raw(many.profiles[:profiles_taken].copy()))
                if event["inside"]:
                    event["peak"] = event_peak
                if returned == compiled_kernels.RETURNED_MAX_STEPS:
                    raise step_budget_spent()
                if returned == compiled_kernels.RETURNED_COLLAPSE:
                    raise step_collapsed()
                if steps == before:
                    continue
            else:
                if steps >= max_steps:
                    raise step_budget_spent()
                h = min(h, duration - t)
                y_new, k7, speed_new, stress_new, norm = trial(t, y, h, k1)
                evaluations += 6
                norm, h, verdict = compiled_kernels.judged_step(norm, h, t)
                if verdict != compiled_kernels.ACCEPTED:
                    rejected += 1
                    after_rejection = True
                    if verdict == compiled_kernels.COLLAPSED:
                        raise step_collapsed()
                    continue
                t_old = t
                t, y, k1, speed, stress = t + h, y_new, k7, speed_new, stress_new
                steps += 1
                min_step, max_step = min(min_step, h), max(max_step, h)
                h *= next_step_factor(norm, previous_norm, after_rejection, rtol)
                previous_norm, after_rejection = max(norm, 1e-4), False
                stations_store.append(station_row(t, y, speed, stress))
                if strain:
                    streams[3].append(strain_row(t, y, speed))
                previous_peak, peak = peak, float(speed.max())
            # the last accepted step: the event and profile records (every earlier step of a compiled call had none)
            previous_log_peak, log_peak = math.log(max(previous_peak, 1e-300)), math.log(max(peak, 1e-300))
            if not event["inside"] and peak > event_speed:
                # an event under way from t = 0 (a nucleation patch that starts fast, SEAS BP5) starts at 0
                fraction = max(0.0, (log_threshold - previous_log_peak) / (log_peak - previous_log_peak))
                event.update(inside=True, start=t_old + fraction * (t - t_old),
                             hypocentre=float(fault.depth[int(np.argmax(speed))]), peak=peak)
                event_slip = y[:count].copy()
            elif event["inside"]:
                event["peak"] = max(event["peak"], peak)
                if peak < event_speed:
                    fraction = (log_threshold - previous_log_peak) / (log_peak - previous_log_peak)
                    end = t_old + fraction * (t - t_old)
                    events_store.append(np.concatenate([[event["start"], end, event["hypocentre"], event["peak"], 0.0],
                                                        y[:count] - event_slip]))
                    event["inside"] = False
            if peak > event_speed:
                if t - last_coseismic >= coseismic_interval:
                    profiles_store.append(profile_row(t, y, speed))
                    last_coseismic = t
            elif t - last_profile >= profile_interval:
                profiles_store.append(profile_row(t, y, speed))
                last_profile = t
            now = clock.perf_counter()
            if progress and now - last_report > 1.0:
                progress(int(t / YEAR), int(math.ceil(duration / YEAR)))
                last_report = now
            if checkpoint is not None and (now - last_save > checkpoint_every or steps == stop_after_steps):
                save()
                last_save = now
                if steps == stop_after_steps:
                    raise _Stopped(t)
            if time_limit is not None and now - started > time_limit:
                if checkpoint is not None:
                    save()
                raise OverBudget(t, now - started)
        if progress:
            progress(int(math.ceil(duration / YEAR)), int(math.ceil(duration / YEAR)))
        wall = wall_before + clock.perf_counter() - started
        if checkpoint is not None:
            save()
        event_rows = events_store.read()
    except BaseException as exc:
        # a fresh run that failed leaves nothing behind; a stop, an interrupt or a resumed run keeps the last
        # checkpoint (a resume truncates what followed it); one stopped before its first checkpoint has nothing
        # to resume, so it too leaves nothing
        stopped = isinstance(exc, (_Stopped, KeyboardInterrupt))
        if checkpoint is not None and not resume and not (stopped and checkpoint.is_file()):
            for stream in streams:
                stream.remove()
            checkpoint.unlink(missing_ok=True)
        raise
    finally:
        for stream in streams:
            stream.close()
    # a run with a folder leaves its station series and profiles on disk, read when indexed (memory flat in the
    # run's length: issue 43); times and the events, a few numbers a row, are read now
    width = recorder.depths.size
    stations_out = {name: stations_store.columns(slice(1 + i * width, 1 + (i + 1) * width))
                    for i, name in enumerate(STATION_FIELDS)}
    profile_times = np.asarray(profiles_store.columns(slice(0, 2)))
    events = {"start": event_rows[:, 0], "end": event_rows[:, 1], "hypocentre_depth": event_rows[:, 2],
              "peak_slip_rate": event_rows[:, 3], "slip": event_rows[:, 5:]}
    run = Fault2DRun(fault, recorder.depths, np.asarray(stations_store.columns(slice(0, 1)))[:, 0], stations_out,
                     profile_times[:, 0], profile_times[:, 1], profiles_store.columns(slice(2, count + 2)),
                     profiles_store.columns(slice(count + 2, 2 * count + 2)), events, steps, rejected, evaluations,
                     wall, duration, rtol, operator.method, y[:count].copy(), y[count:].copy(), t, min_step, max_step,
                     resumed_from)
    run.notes.extend(notes)
    if strain:
        sites, positions = recorder.depths.size, surface_positions.size
        run.plane_strain = {"normal_stress": streams[3].columns(slice(1, 1 + sites)),
                            "surface_positions": surface_positions,
                            "surface_displacement": np.asarray(streams[3].columns(
                                slice(1 + sites, 1 + sites + 2 * positions))).reshape(-1, 2, positions),
                            "surface_velocity": np.asarray(streams[3].columns(
                                slice(1 + sites + 2 * positions, 1 + sites + 4 * positions))).reshape(-1, 2, positions)}
    if event["inside"]:
        run.notes.append(f"an event was under way at the end (started at {event['start'] / YEAR:.6g} yr); it is not "
                         "in the catalogue")
    return run


class _Stopped(Exception):
    """Raised by ``stop_after_steps``: the run stopped as a kill would, with its checkpoint written."""

    def __init__(self, time):
        super().__init__(f"stopped at t = {time:.17g} s")
        self.time = time


class OverBudget(_Stopped):
    """Raised past ``time_limit``: the run stopped, its checkpoint written where it has a folder."""

    def __init__(self, t: float, seconds: float):
        super().__init__(t)
        self.t, self.seconds = t, seconds


def _checkpoint_layout(count: int, streams: int = len(STREAM_FILES)) -> dict:
    """What a checkpoint of a run on ``count`` elements with ``streams`` record streams holds: (dtype kinds, shape)
    per array."""
    state, field = (2 * count,), (count,)
    return {"version": ("iu", ()), "digest": ("U", ()), "t": ("f", ()), "y": ("f", state), "h": ("f", ()),
            "k1": ("f", state), "u": ("f", (None,)), "speed": ("f", field), "stress": ("f", field),
            "counters": ("iu", (3,)), "steps_range": ("f", (3,)), "controller": ("f", (2,)), "event": ("U", ()), "event_slip": ("f", field),
            "profile_times": ("f", (2,)), "rows": ("iu", (streams,)), "stream_digests": ("U", (streams,))}


def _event_record(text, path: Path) -> dict:
    """The event under way at the checkpoint, checked (the checkpoint's digest already vouches for it)."""
    try:
        event = json.loads(str(text))
        return {"inside": bool(event["inside"]), "start": float(event["start"]),
                "hypocentre": float(event["hypocentre"]), "peak": float(event["peak"])}
    except (ValueError, KeyError, TypeError):
        raise InputError(f"the checkpoint {str(path)!r} holds no readable event record; start the run again "
                         "without --resume") from None


def _read_checkpoint(path: Path, digest: str, count: int, streams: int = len(STREAM_FILES)) -> dict:
    saved = read_checkpoint(path, _checkpoint_layout(count, streams), "2-D fault checkpoint")
    if int(saved["version"]) != CHECKPOINT_VERSION:
        raise InputError(f"{path} is a checkpoint of another faultslip version; start the run again")
    if str(saved.get("digest")) != digest:
        raise InputError(f"{path} is the checkpoint of a different run (scene, rtol, stations or duration changed); "
                         "start again without --resume, or restore the settings it was made with")
    return saved
