r"""A chain of spring-blocks (Burridge & Knopoff 1967), event by event: analytic sticks, exact slips.

N blocks of mass m, each pulled by a leaf spring k_p (and a dashpot c, in parallel) from a plate moving
at V, neighbours joined by coupling springs k_c (free ends). Block i holds while the force on it,

.. math:: F_i = k_p (V t - x_i) + c (V - \dot x_i) + k_c \sum_{j \sim i} (x_j - x_i),

stays within its static limit, |F_i| <= W \mu_{s,i} (the seed's rate-law static friction, a threshold for
each block); a slipping block feels the kinetic friction W \mu_k against its motion:

.. math:: m \ddot x_i = F_i - W \mu_k \, \mathrm{sign}(\dot x_i).

A block pulled back past -W mu_s,i by its neighbours slips backwards, as Burridge & Knopoff's blocks may.

**Sticks** are analytic: with every block held, every force grows at k_p V, so the next block to fail is
the one with the least headroom W mu_s,i - F_i, after headroom / (k_p V). Nothing is stepped through the
interseismic time.

**Slips** are exact. With the slipping set S fixed, the equations are linear with constant coefficients
and a forcing linear in time: m x'' + c x' + K_S x = A + B tau, K_S the tridiagonal stiffness of S
(the held blocks fixed). Its modes (K_S = Phi Lambda Phi^T, scipy's ``eigh_tridiagonal``) are damped
oscillators with the closed-form solution

.. math:: q_j(\tau) = P_{0j} + P_{1j} \tau + e^{-\gamma \tau} (C_j \cos \omega_{dj} \tau + D_j \sin \omega_{dj} \tau),

gamma = c / 2m, omega_dj^2 = lambda_j / m - gamma^2 (every mode underdamped: c < 2 sqrt(k_p m)). A
sub-phase ends at the first of: a slipping block's speed returning to zero (it sticks if |F_i| <= W mu_s,i,
else slips on, in the direction of F_i), or a held block's |F_i| reaching its limit (it joins). Each is bracketed on a grid of 32
points per period of the fastest mode and located by Brent's method on the closed form to 1e-13 of the
step. A speed, or a held block's headroom W mu_s,i - |F_i|, positive at two grid points but within its curvature
bound of zero (k_c times the slipping neighbours' accelerations, for a force) is searched between them for a touch
(:func:`_dip`): a force that rose past its limit and back between points 32 ms apart once went unjoined.
scipy's integrators, the other slip solvers, see a sign change only at their steps' ends: each speed's and
headroom's least value along the slip is located too (:func:`_passed_over`), and one at or below zero is a change
a step passed over. Blocks that stop or fail together (identical blocks) do so in one sub-phase. An event ends
when no block slips.

The same loop runs compiled (``_chain.c``, built at install where a C compiler is) as the slip solver
``closed_form_compiled``, which ``auto`` chooses when it was built: the same sticks, sub-phases, grid and
tolerances, with each run of neighbouring slipping blocks' modes in closed form (the discrete sine and
cosine transforms' eigenpairs) rather than from an eigensolver. Python's ``closed_form`` stays as the
reference it is tested against.

Failures are never silent: a slip that outlives its horizon, more sub-phases than the budget, or a state whose
forces or bounds leave double precision raise :class:`~faultslip.errors.SolverError`, saying which and what to do.
"""

from __future__ import annotations

import math
import time as clock
from dataclasses import dataclass, field

import numpy as np

from faultslip.errors import InputError, SolverError
from faultslip.datasets import ToXarray
from faultslip.units import takes_units

try:
    from faultslip.models.spring_chain import _chain
except ImportError:  # built only where a C compiler was found at install
    _chain = None

#: Grid points per period of the fastest mode that bracket a sub-phase's end.
SAMPLES_PER_PERIOD = 32
#: Relative tolerance within which blocks stop or fail together.
TOGETHER = 1e-10
#: An event that lasts this many of a lone block's periods without every block sticking is steady sliding.
STEADY_PERIODS = 200


@takes_units(mass="mass", leaf_stiffness="stiffness", coupling_stiffness="stiffness", normal_load="force",
             platform_speed="speed", dashpot="damping")
@dataclass(frozen=True)
class Chain:
    """A spring-block chain in SI: N blocks, their static limits and the shared kinetic friction.

    Parameters
    ----------
    mass : float
        m of each block (kg).
    leaf_stiffness : float
        k_p, the spring from each block to the plate (N/m).
    coupling_stiffness : float
        k_c, the spring between neighbours (N/m; 0 uncouples them).
    normal_load : float
        W on each block (N).
    platform_speed : float
        V, the plate's speed (m/s).
    static_friction : array
        mu_s,i of each block (its length is the number of blocks).
    kinetic_friction : float
        mu_k while a block slips (below every mu_s,i).
    dashpot : float
        c between each block and the plate (N s/m), below 2 sqrt(k_p m).
    name : str
        For reports.
    """

    mass: float
    leaf_stiffness: float
    coupling_stiffness: float
    normal_load: float
    platform_speed: float
    static_friction: np.ndarray
    kinetic_friction: float
    dashpot: float = 0.0
    name: str = "spring-block chain"

    def __post_init__(self):
        for key in ("mass", "leaf_stiffness", "normal_load", "platform_speed"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"the chain's {key.replace('_', ' ')} must be positive, got {value!r}")
        if not (math.isfinite(self.coupling_stiffness) and self.coupling_stiffness >= 0):
            raise InputError(f"the chain's coupling stiffness must be zero or positive, got {self.coupling_stiffness!r}")
        static = np.asarray(self.static_friction, float)
        if static.ndim != 1 or static.size < 1:
            raise InputError("the chain needs a static friction for each of at least one block")
        if not (math.isfinite(self.kinetic_friction) and self.kinetic_friction >= 0):
            raise InputError(f"the kinetic friction must be zero or positive, got {self.kinetic_friction!r}")
        if not np.all(np.isfinite(static)) or not np.all(static > self.kinetic_friction):
            raise InputError(f"every block's static friction must exceed the kinetic friction {self.kinetic_friction:g} "
                             f"(the smallest is {static.min():g}): without a drop there is no stick-slip")
        critical = 2 * math.sqrt(self.leaf_stiffness * self.mass)
        if not (math.isfinite(self.dashpot) and 0 <= self.dashpot < critical):
            raise InputError(f"the dashpot must be from 0 to below critical damping 2 sqrt(k_p m) = {critical:.4g} N s/m, "
                             f"got {self.dashpot!r}")
        object.__setattr__(self, "static_friction", static)

    @property
    def blocks(self) -> int:
        return int(self.static_friction.size)

    @property
    def damping_ratio(self) -> float:
        """zeta = c / (2 sqrt(k_p m)), of a block alone."""
        return self.dashpot / (2 * math.sqrt(self.leaf_stiffness * self.mass))

    def neighbours(self) -> np.ndarray:
        """How many neighbours each block has (free ends)."""
        degree = np.full(self.blocks, 2.0)
        degree[[0, -1]] = 1.0
        if self.blocks == 1:
            degree[:] = 0.0
        return degree

    def forces(self, x: np.ndarray, v: np.ndarray, t: float) -> np.ndarray:
        """F_i on every block at positions ``x``, speeds ``v`` and time ``t`` (friction aside)."""
        coupling = np.zeros_like(x)
        if self.blocks > 1:
            difference = np.diff(x)
            coupling[:-1] += difference
            coupling[1:] -= difference
        return (self.leaf_stiffness * (self.platform_speed * t - x) + self.dashpot * (self.platform_speed - v)
                + self.coupling_stiffness * coupling)


@dataclass
class ChainRun(ToXarray):
    """A chain's catalogue: one row per event (SI), and the state it ended in.

    Attributes
    ----------
    start, end : array
        Each event's first failure and last stop (s).
    first_block : array
        The block that failed first (the hypocentre).
    blocks_slipped : array
        How many blocks slipped in each event.
    slip : array
        (events, blocks): each block's slip in each event (m).
    peak_speed : array
        Each event's fastest block speed (m/s).
    """
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'start': 's', 'end': 's', 'first_block': '1', 'blocks_slipped': '1', 'slip': 'm', 'peak_speed': 'm/s', 'subphases': '1', 'wall_time': 's', 'final_position': 'm', 'final_time': 's'}
    DIMENSIONS = {'start': 'event', 'end': 'event', 'first_block': 'event', 'blocks_slipped': 'event', 'peak_speed': 'event'}

    chain: Chain
    start: np.ndarray  # (events,) s
    end: np.ndarray  # (events,) s
    first_block: np.ndarray  # (events,) the block that failed first (the hypocentre)
    blocks_slipped: np.ndarray  # (events,) how many blocks slipped
    slip: np.ndarray  # (events, blocks) m
    peak_speed: np.ndarray  # (events,) m/s
    subphases: int
    wall_time: float
    final_position: np.ndarray
    final_time: float
    notes: list = field(default_factory=list)

    @property
    def events(self) -> int:
        return int(self.start.size)

    def extents(self) -> tuple[np.ndarray, np.ndarray]:
        """The first and last block each event moved (what the catalogue's figures draw)."""
        return slipped_extents(self.slip)

    @property
    def total_slip(self) -> np.ndarray:
        """Slip summed over the blocks of each event (m): the event's potency per patch area."""
        return self.slip.sum(axis=1)


def slipped_extents(slip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, last) block with a nonzero slip in each row of ``slip`` (events x blocks); 0 for an empty row."""
    moved = slip != 0
    some = moved.any(axis=1)
    return (np.where(some, moved.argmax(axis=1), 0),
            np.where(some, slip.shape[1] - 1 - moved[:, ::-1].argmax(axis=1), 0))


class _Modes:
    """The closed-form motion of the slipping set S over one sub-phase (see the module)."""

    def __init__(self, chain: Chain, slipping: np.ndarray, degree: np.ndarray, x: np.ndarray, v: np.ndarray,
                 t0: float, direction: np.ndarray):
        from scipy.linalg import eigh_tridiagonal  # heavy: imported where used

        m, kp, kc, V = chain.mass, chain.leaf_stiffness, chain.coupling_stiffness, chain.platform_speed
        self.index = slipping
        diagonal = kp + kc * degree[slipping]
        held = np.zeros(chain.blocks, bool)
        held[:] = True
        held[slipping] = False
        pull = np.zeros(slipping.size)  # k_c times the held neighbours' positions
        for offset in (-1, 1):
            neighbour = slipping + offset
            inside = (neighbour >= 0) & (neighbour < chain.blocks)
            fixed = np.zeros(slipping.size, bool)
            fixed[inside] = held[neighbour[inside]]
            pull[fixed] += kc * x[neighbour[fixed]]
        constant = (kp * V * t0 + chain.dashpot * V - chain.normal_load * chain.kinetic_friction * direction[slipping]
                    + pull)
        if slipping.size == 1:
            values, vectors = diagonal, np.ones((1, 1))
        else:
            adjacent = np.diff(slipping) == 1
            values, vectors = eigh_tridiagonal(diagonal, np.where(adjacent, -kc, 0.0))
        self.vectors = vectors
        gamma = chain.dashpot / (2 * m)
        omega2 = values / m
        self.gamma, self.omega_d = gamma, np.sqrt(omega2 - gamma ** 2)
        alpha = vectors.T @ constant / m
        beta = vectors.T @ np.full(slipping.size, kp * V) / m
        self.p1 = beta / omega2
        self.p0 = (alpha - 2 * gamma * self.p1) / omega2
        q0, dq0 = vectors.T @ x[slipping], vectors.T @ v[slipping]
        self.c = q0 - self.p0
        self.d = (dq0 - self.p1 + gamma * self.c) / self.omega_d

    def modal(self, tau):
        """(q, dq/dt) of every mode at ``tau``: modes x times for an array of times, or vectors for a number."""
        tau = np.asarray(tau, float)
        if tau.ndim:
            tau = tau[None, :]
            wd, c, d, p0, p1 = (a[:, None] for a in (self.omega_d, self.c, self.d, self.p0, self.p1))
        else:
            wd, c, d, p0, p1 = self.omega_d, self.c, self.d, self.p0, self.p1
        decay = np.exp(-self.gamma * tau)
        cos, sin = np.cos(wd * tau), np.sin(wd * tau)
        q = p0 + p1 * tau + decay * (c * cos + d * sin)
        dq = p1 + decay * ((-self.gamma * c + wd * d) * cos + (-self.gamma * d - wd * c) * sin)
        return q, dq

    def state(self, tau):
        """(positions, speeds) of the slipping blocks at ``tau`` (a number, or an array: blocks x times)."""
        q, dq = self.modal(tau)
        return self.vectors @ q, self.vectors @ dq

    def speed(self, tau: float, row: int) -> float:
        """The speed of slipping block ``row`` at ``tau`` (one row of the modes: cheap, for root finding)."""
        return float(self.vectors[row] @ self.modal(tau)[1])

    def speed_curvature_bound(self) -> np.ndarray:
        """A bound on |d^2 v / d tau^2| of each slipping block over the sub-phase (m/s^3): each mode's speed is
        p1 + e^(-gamma tau) R cos(omega tau + phase), R = sqrt(gamma^2 + omega^2) sqrt(c^2 + d^2), and two more
        derivatives multiply R by gamma^2 + omega^2 at most (gamma >= 0: the decay only shrinks it)."""
        with np.errstate(over="ignore", invalid="ignore"):  # an overflowing bound is reported by the caller
            amplitude = np.hypot(self.c, self.d) * (self.gamma ** 2 + self.omega_d ** 2) ** 1.5
            return np.abs(self.vectors) @ amplitude

    def acceleration_bound(self) -> np.ndarray:
        """A bound on |d^2 x / d tau^2| of each slipping block (m/s^2): each mode's position is p0 + p1 tau +
        e^(-gamma tau) sqrt(c^2 + d^2) cos(omega tau + phase), whose second derivative is at most
        sqrt(c^2 + d^2) (gamma^2 + omega^2)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return np.abs(self.vectors) @ (np.hypot(self.c, self.d) * (self.gamma ** 2 + self.omega_d ** 2))


#: Halvings of a grid interval before a speed that stays within its curvature bound of zero is taken not to cross it
#: (the dip it could hide is then below 1e-12 of the bound at the grid's spacing).
DIP_DEPTH = 20


def _dip(speed, low: float, at_low: float, high: float, at_high: float, curvature: float, depth: int = 0):
    """The first point of [low, high] found where ``speed`` (positive at both ends) is at or below zero, with the
    last point before it where it is positive: (positive, nonpositive), or None where it cannot dip below zero.

    Between two points h apart a function whose second derivative is at most ``curvature`` lies above the line
    through them less curvature h^2 / 8; where both ends clear that, it cannot reach zero. Else the interval is
    halved (the grid sees only its points: a block whose speed dipped below zero for 0.46 ms between points 1.1 ms
    apart was not stopped, and slid backwards against forward friction)."""
    if min(at_low, at_high) > curvature * (high - low) ** 2 / 8 or depth >= DIP_DEPTH:
        return None
    middle = 0.5 * (low + high)
    at_middle = speed(middle)
    if at_middle <= 0.0:
        return low, middle
    return (_dip(speed, low, at_low, middle, at_middle, curvature, depth + 1)
            or _dip(speed, middle, at_middle, high, at_high, curvature, depth + 1))


def _first_crossing(values: np.ndarray, at_or_below: bool) -> np.ndarray:
    """Index of the first grid point of each row at or below zero (``at_or_below``) or at or above zero; -1 if
    none."""
    hit = values <= 0.0 if at_or_below else values >= 0.0
    first = np.argmax(hit, axis=1)
    return np.where(hit.any(axis=1), first, -1)


#: How a slip sub-phase is solved: the closed form (exact), or scipy's integrators with terminal events (the
#: generic way, and the baseline the closed form's speed is measured against in benchmarks/spring_chain_speed.py).
SLIP_SOLVERS = ("auto", "closed_form", "closed_form_compiled", "DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
#: the solvers that integrate (scipy's)
INTEGRATORS = SLIP_SOLVERS[3:]


def compiled_available() -> bool:
    """Whether the compiled event loop (``_chain.c``) was built with this install."""
    return _chain is not None


def chosen_solver(slip_solver: str) -> str:
    """What ``slip_solver`` runs: ``auto`` is the compiled closed form where it was built, else Python's."""
    if slip_solver == "auto":
        return "closed_form_compiled" if compiled_available() else "closed_form"
    return slip_solver


@takes_units(initial_position="length")
def simulate_chain(chain: Chain, events: int, *, initial_position=None, max_subphases: int | None = None,
                   slip_solver: str = "auto", rtol: float = 1e-10, steps_per_period: float | None = None) -> ChainRun:
    """Run ``chain`` from rest until ``events`` events have happened (see the module).

    Parameters
    ----------
    chain : Chain
        The chain.
    events : int
        How many events to record.
    initial_position : array, optional
        Each block's position at t = 0 (m; default all at 0, the plate's springs unstretched).
    max_subphases : int, optional
        A budget of slip sub-phases (default 50 per block per event).
    slip_solver : str
        ``auto`` (the compiled closed form where it was built, else Python's), ``closed_form`` (exact, in
        Python), ``closed_form_compiled`` (exact, in C), or a scipy integrator (``DOP853``, ``RK45``, ``Radau``) with terminal events at
        ``rtol``: the same sub-phases, found by integration.
    rtol : float
        The integrator's relative tolerance (not used by the closed form).
    steps_per_period : float, optional
        An integrator's steps at least this many a period of the fastest mode (None: as its error control takes
        them). An integrator's events test signs at its steps' ends; a dip inside a step is found by locating
        each speed's and headroom's least value, a reference run takes many steps so that it does not rely on it.

    Returns
    -------
    ChainRun
    """
    from scipy.optimize import brentq  # heavy: imported where used

    if not (isinstance(events, (int, np.integer)) and events >= 1):
        raise InputError(f"the chain needs at least one event to run, got {events!r}")
    if slip_solver not in SLIP_SOLVERS:
        raise InputError(f"the chain's slip solver must be one of {', '.join(SLIP_SOLVERS)}, got {slip_solver!r}")
    if not 1e-14 <= rtol <= 1e-3:
        raise InputError(f"the chain's rtol must lie from 1e-14 to 1e-3, got {rtol!r}")
    slip_solver = chosen_solver(slip_solver)
    if slip_solver == "closed_form_compiled" and not compiled_available():
        raise InputError("the compiled chain (closed_form_compiled) was not built with this install (no C compiler "
                         "at install); use slip_solver = \"closed_form\", the same scheme in Python")
    n = chain.blocks
    x = np.zeros(n) if initial_position is None else np.array(initial_position, float)
    if x.shape != (n,) or not np.all(np.isfinite(x)):
        raise InputError(f"the initial positions must be {n} finite numbers, one a block")
    v = np.zeros(n)
    t = 0.0
    kp, V, W = chain.leaf_stiffness, chain.platform_speed, chain.normal_load
    limits = W * chain.static_friction
    degree = chain.neighbours()
    budget = max_subphases or 50 * n * events + 1000
    with np.errstate(over="ignore", invalid="ignore"):  # a start past double precision fails below, in words
        start_force = chain.forces(x, v, 0.0)
    if slip_solver == "closed_form_compiled":
        return _compiled(chain, events, x, budget, start_force)
    starts, ends, firsts, sizes, slips, peaks = [], [], [], [], [], []
    subphases = 0
    began = clock.perf_counter()
    scale = chain.normal_load * (chain.static_friction.max() - chain.kinetic_friction)
    slowest_period = 2 * math.pi * math.sqrt(chain.mass / chain.leaf_stiffness)  # a lone block's, the chain's longest
    while len(starts) < events:
        # stick: every force grows at k_p V; the least headroom fails first (and any within TOGETHER of it). A
        # start that holds a block past -W mu_s (neighbours far ahead) lets it go backwards at once.
        with np.errstate(over="ignore", invalid="ignore"):
            force = chain.forces(x, v, t)
        if not np.all(np.isfinite(force)):
            raise _overflow(chain, t, x)
        headroom = np.where(force < -limits, -np.inf, limits - force)
        wait = max(float(headroom.min()), 0.0) / (kp * V)
        t += wait
        headroom -= kp * V * wait
        slipping = np.flatnonzero(headroom <= TOGETHER * scale)
        first = int(slipping[np.argmin(headroom[slipping])])
        direction = np.where(force < -limits, -1.0, 1.0)
        x_before, t_start, peak = x.copy(), t, 0.0
        slipped = np.zeros(n, bool)
        while slipping.size:
            subphases += 1
            if subphases > budget:
                raise SolverError(f"the chain: more than {budget} slip sub-phases at t = {t:.6g} s; raise "
                                  "max_subphases, or fewer blocks or events")
            if t - t_start > STEADY_PERIODS * slowest_period:  # a slip that never ends is steady sliding
                raise _steady(chain, slipping[:5], (t - t_start) / slowest_period, start_force if not starts else None)
            slipped[slipping] = True
            if slip_solver == "closed_form":
                modes = _Modes(chain, slipping, degree, x, v, t, direction)
                tau, stops, joins = _next_change(chain, modes, slipping, x, v, t, limits, direction, brentq)
                xs, vs = modes.state(tau)
                peak = max(peak, float(_peak_speed(modes, tau)))
            else:
                tau, stops, joins, xs, vs, fastest = _integrated_change(chain, slipping, x, v, t, limits, direction,
                                                                        slip_solver, rtol, steps_per_period)
                peak = max(peak, fastest)
            x[slipping], v[slipping] = xs, vs
            t += tau
            v[slipping[stops]] = 0.0
            force = chain.forces(x, v, t)
            stopped = slipping[stops]
            # a stopped block holds if its limit does; else it slips on, the way its force pushes
            stay = stopped[np.abs(force[stopped]) > limits[stopped]]
            direction[stay] = np.sign(force[stay])
            direction[joins] = np.where(force[joins] < 0, -1.0, 1.0)
            held = np.setdiff1d(stopped, stay)
            slipping = np.union1d(np.setdiff1d(slipping, held), joins)
        starts.append(t_start)
        ends.append(t)
        firsts.append(first)
        sizes.append(int(slipped.sum()))
        slips.append(x - x_before)
        peaks.append(peak)
    return ChainRun(chain, np.array(starts), np.array(ends), np.array(firsts), np.array(sizes), np.array(slips),
                    np.array(peaks), subphases, clock.perf_counter() - began, x.copy(), t)


def _steady(chain: Chain, blocks, periods: float, start_force: np.ndarray | None) -> SolverError:
    """The failure of a slip that has not ended in STEADY_PERIODS of a lone block's periods: steady sliding, or, in
    the first event (``start_force`` given), a start stretched so far beyond the limits that the chain is still
    unloading it."""
    limit = chain.normal_load * float(chain.static_friction.max())
    stored = 0.0 if start_force is None else float(np.abs(start_force).max())
    where = (f"block(s) {', '.join(str(int(b)) for b in blocks)} have slipped for {periods:.0f} of a block's periods "
             "without sticking")
    if stored > 10 * limit:
        return SolverError(
            f"the chain is still unloading its start: {where}, and the initial positions put forces of up to "
            f"{stored:.3g} N on blocks that hold at most {limit:.3g} N; start the blocks within about "
            f"{limit / chain.leaf_stiffness:.3g} m of each other and of the plate (W mu_s / k_p)")
    return SolverError(
        f"the chain slides steadily: {where}, as a slider above its critical loading rate does (damping ratio "
        f"{chain.damping_ratio:.3g}); lower the damping or the plate speed for stick-slip")


def _overflow(chain: Chain, t: float, x: np.ndarray) -> SolverError:
    """The failure of a state whose forces, or the bounds the slip's grid is searched by, leave double precision."""
    reach = float(np.nanmax(np.abs(np.where(np.isfinite(x), x, np.inf))))
    within = chain.normal_load * float(chain.static_friction.max()) / chain.leaf_stiffness
    return SolverError(
        f"the chain's state overflowed double precision at t = {t:.6g} s (block positions up to {reach:.3g} m): its "
        f"forces, or the bounds its slips are searched by, are no longer finite, and no later event could be "
        f"trusted; start the blocks within about {within:.3g} m of each other and of the plate (W mu_s / k_p)")


def _compiled(chain: Chain, events: int, x: np.ndarray, budget: int, start_force: np.ndarray) -> ChainRun:
    """The loop of :func:`simulate_chain` in C (``_chain.run``), with the same failures."""
    n = chain.blocks
    start, end, peak = np.zeros(events), np.zeros(events), np.zeros(events)
    first, size = np.zeros(events, np.int64), np.zeros(events, np.int64)
    slip = np.zeros((events, n))
    began = clock.perf_counter()
    status, done, subphases, t, t_start, count, blocks = _chain.run(
        chain.mass, chain.leaf_stiffness, chain.coupling_stiffness, chain.normal_load, chain.platform_speed,
        chain.kinetic_friction, chain.dashpot, np.ascontiguousarray(chain.normal_load * chain.static_friction), x,
        0.0, events, budget, start, end, first, size, slip, peak)
    if status == 1:
        raise SolverError(f"the chain: more than {budget} slip sub-phases at t = {t:.6g} s; raise max_subphases, or "
                          "fewer blocks or events")
    if status == 2:
        slowest_period = 2 * math.pi * math.sqrt(chain.mass / chain.leaf_stiffness)
        raise _steady(chain, blocks, (t - t_start) / slowest_period, start_force if done == 0 else None)
    if status == 4:
        raise _overflow(chain, t, x)
    if status == 3:
        raise SolverError(f"the chain: a slip of {count} block(s) from t = {t:.6g} s neither ended nor spread within 200 "
                          "of its slowest periods; the coupling may be too stiff for the leaf springs")
    return ChainRun(chain, start, end, first, size, slip, peak, int(subphases), clock.perf_counter() - began, x.copy(),
                    float(t))


def _peak_speed(modes: _Modes, tau: float, samples: int = 16) -> float:
    """The largest block speed over the sub-phase, on a grid (a record, not a decision)."""
    grid = np.linspace(0.0, tau, samples)
    return float(np.abs(modes.state(grid)[1]).max())


def _next_change(chain, modes, slipping, x, v, t0, limits, direction, brentq):
    """(tau, which slipping blocks stop, which held blocks join) at the sub-phase's first change."""
    n = chain.blocks
    kp, kc, V = chain.leaf_stiffness, chain.coupling_stiffness, chain.platform_speed
    held = np.ones(n, bool)
    held[slipping] = False
    # held blocks next to a slipping one feel it; the rest only the plate (linear in time, exact below)
    near = np.zeros(n, bool)
    for offset in (-1, 1):
        neighbour = slipping + offset
        neighbour = neighbour[(neighbour >= 0) & (neighbour < n)]
        near[neighbour] = True
    near &= held
    near_index = np.flatnonzero(near)
    far_index = np.flatnonzero(held & ~near)
    force0 = chain.forces(x, v, t0)
    far_wait = (limits[far_index] - force0[far_index]) / (kp * V) if far_index.size else np.empty(0)
    period = 2 * math.pi / float(modes.omega_d.max())
    step = period / SAMPLES_PER_PERIOD
    slowest = 2 * math.pi / float(modes.omega_d.min())
    # a near block's force: the plate's pull, its held neighbours' (fixed over the sub-phase), and k_c times each
    # slipping neighbour's position, kept as (row, position in S) pairs
    position_in_s = np.full(n, -1)
    position_in_s[slipping] = np.arange(slipping.size)
    fixed = force0[near_index] - kp * V * t0  # at tau = 0, less the plate's share that grows with time
    rows, moving = [], []
    for offset in (-1, 1):
        other = near_index + offset
        inside = (other >= 0) & (other < n)
        slips = np.zeros(near_index.size, bool)
        slips[inside] = position_in_s[other[inside]] >= 0
        fixed[slips] -= kc * x[other[slips]]  # its position moves: taken from the closed form instead
        rows.extend(np.flatnonzero(slips).tolist())
        moving.extend(position_in_s[other[slips]].tolist())
    rows, moving = np.array(rows, int), np.array(moving, int)

    def near_force(xs, tau):
        """Force on each near held block (rows) at the grid's times (columns); ``xs`` the slipping blocks' positions
        (blocks x times)."""
        total = fixed[:, None] + kp * V * (t0 + np.asarray(tau, float))[None, :]
        np.add.at(total, rows, kc * xs[moving])
        return total

    pulls = [moving[rows == row] for row in range(near_index.size)]  # each near block's slipping neighbours

    def headroom(tau, row):
        """A near held block's W mu_s - |F| at ``tau`` (one row: cheap, for root finding)."""
        q = modes.modal(tau)[0]
        force = fixed[row] + kp * V * (t0 + tau) + kc * float((modes.vectors[pulls[row]] @ q).sum())
        return float(limits[near_index[row]] - abs(force))

    # |F|'' of a near block is k_c times its slipping neighbours' accelerations (the plate's pull is linear)
    force_curvature = np.zeros(near_index.size)
    np.add.at(force_curvature, rows, kc * modes.acceleration_bound()[moving] if rows.size else 0.0)

    # windows that grow from one period of the fastest mode: most sub-phases end within a few (a block stops or a
    # neighbour joins), so the closed form is evaluated little beyond the change; the 200 windows reach far past
    # 200 of the slowest periods
    start, points = 0.0, SAMPLES_PER_PERIOD
    horizon = 200 * slowest
    curvature = modes.speed_curvature_bound()
    if not np.all(np.isfinite(curvature)):  # the dip search would halve its way through every grid interval
        raise _overflow(chain, t0, x)
    along = direction[slipping]
    at_start = modes.state(0.0)[1] * along
    if not np.all(np.isfinite(force_curvature)):
        raise _overflow(chain, t0, x)
    room_at_start = limits[near_index] - np.abs(near_force(modes.state(0.0)[0][:, None], np.zeros(1))[:, 0])
    while start < horizon:
        grid = start + step * np.arange(1, points + 1)
        xs, vs = modes.state(grid)
        candidates = []  # (bracket low, bracket high, kind, row)
        speeds = vs * along[:, None]
        stop = _first_crossing(speeds, at_or_below=True)
        for row in np.flatnonzero(stop >= 0):
            k = int(stop[row])
            low = grid[k - 1] if k > 0 else start
            candidates.append((low, grid[k], "stop", int(row)))
        # a speed positive at two grid points may dip below zero between them: where it comes within its curvature
        # bound of zero, look between (before the row's first crossing on the grid)
        times = np.concatenate(([start], grid))
        values = np.concatenate((at_start[:, None], speeds), axis=1)
        near_zero = np.minimum(values[:, :-1], values[:, 1:]) <= curvature[:, None] * step ** 2 / 8
        for row, k in zip(*np.nonzero(near_zero & (values[:, :-1] > 0) & (values[:, 1:] > 0))):
            if 0 <= stop[row] <= k:
                continue
            found = _dip(lambda tau, row=row: modes.speed(tau, row) * along[row], times[k], values[row, k],
                         times[k + 1], values[row, k + 1], curvature[row])
            if found is not None:
                candidates.append((found[0], found[1], "stop", int(row)))
                stop[row] = k
        at_start = speeds[:, -1]
        if near_index.size:
            room = limits[near_index, None] - np.abs(near_force(xs, grid))
            join = _first_crossing(room, at_or_below=True)
            for row in np.flatnonzero(join >= 0):
                k = int(join[row])
                candidates.append((grid[k - 1] if k > 0 else start, grid[k], "join", int(row)))
            # as for the speeds: a force within its curvature bound of the limit may touch it between grid points
            values = np.concatenate((room_at_start[:, None], room), axis=1)
            near_zero = np.minimum(values[:, :-1], values[:, 1:]) <= force_curvature[:, None] * step ** 2 / 8
            for row, k in zip(*np.nonzero(near_zero & (values[:, :-1] > 0) & (values[:, 1:] > 0))):
                if 0 <= join[row] <= k:
                    continue
                found = _dip(lambda tau, row=row: headroom(tau, row), times[k], values[row, k], times[k + 1],
                             values[row, k + 1], force_curvature[row])
                if found is not None:
                    candidates.append((found[0], found[1], "join", int(row)))
                    join[row] = k
            room_at_start = room[:, -1]
        for row, wait in enumerate(far_wait):
            if wait <= grid[-1]:
                candidates.append((max(wait, 0.0), max(wait, 0.0), "far", row))
        if candidates:
            break
        start, points = grid[-1], min(2 * points, 64 * SAMPLES_PER_PERIOD)
    else:
        raise SolverError(f"the chain: a slip of {slipping.size} block(s) from t = {t0:.6g} s neither ended nor spread "
                          "within 200 of its slowest periods; the coupling may be too stiff for the leaf springs")
    # refine in order of their brackets: a later bracket matters only if it starts before the best root so far
    candidates.sort(key=lambda item: (item[0], item[1]))
    roots, best = [], math.inf
    for low, high, kind, row in candidates:
        if low > best:
            break
        if kind == "far":
            root = low
        else:
            # g > 0 before the change and <= 0 after it: a stopping block's speed along its slip, or a joining
            # block's headroom W mu_s - |F|
            if kind == "stop":
                def g(tau, row=row):
                    return modes.speed(tau, row) * direction[slipping[row]]
            else:
                def g(tau, row=row):
                    return headroom(tau, row)
            # a block starting from rest steps off its zero speed at tau = 0; a held block already at its limit joins
            a = low if g(low) > 0.0 else (_off_zero(g, low, high) if kind == "stop" else None)
            if a is None:  # no room before the change: it happens at the bracket's start
                root = low
            elif g(high) > 0.0:  # the grid saw the change and the closed form, to round-off, not quite: its end
                root = high
            else:
                root = brentq(g, a, high, xtol=1e-13 * max(high, 1e-300), rtol=4 * np.finfo(float).eps)
        roots.append((root, kind, row))
        best = min(best, root)
    tau = min(root for root, _, _ in roots)
    # everything that happens within TOGETHER of tau happens now (identical blocks stop and fail together)
    xs, vs = modes.state(tau)
    speed_scale = max(float(np.abs(vs).max()), float(np.abs(v[slipping]).max()), 1e-300)
    # at tau = 0 (a block joined at once) the blocks just set going have not stopped: they have not moved
    stops = (vs * direction[slipping] <= TOGETHER * speed_scale) if tau > 0 else np.zeros(slipping.size, bool)
    stops |= np.isin(np.arange(slipping.size), [row for root, kind, row in roots if kind == "stop" and root <= tau])
    joins = []
    if near_index.size:
        excess = np.abs(near_force(xs[:, None], np.array([tau]))[:, 0]) - limits[near_index]
        joins.extend(near_index[excess >= -TOGETHER * np.abs(limits[near_index])].tolist())
        joins.extend(near_index[row] for root, kind, row in roots if kind == "join" and root <= tau)
    if far_index.size:
        joins.extend(far_index[far_wait <= tau * (1 + TOGETHER)].tolist())
    return tau, stops, np.unique(np.array(joins, int))


def _integrated_change(chain, slipping, x, v, t0, limits, direction, solver, rtol, steps_per_period=None):
    """The sub-phase by integration (scipy's ``solve_ivp`` with a terminal event for each slipping block's stop
    and each held neighbour's limit): (tau, stops, joins, positions, speeds, peak speed)."""
    from scipy.integrate import solve_ivp  # heavy: imported where used

    n, count = chain.blocks, slipping.size
    kp, V, W, m = chain.leaf_stiffness, chain.platform_speed, chain.normal_load, chain.mass
    held = np.ones(n, bool)
    held[slipping] = False
    near = np.zeros(n, bool)
    for offset in (-1, 1):
        other = slipping + offset
        near[other[(other >= 0) & (other < n)]] = True
    near_index, far_index = np.flatnonzero(near & held), np.flatnonzero(held & ~near)
    force0 = chain.forces(x, v, t0)
    far_wait = (limits[far_index] - force0[far_index]) / (kp * V) if far_index.size else np.empty(0)
    omega = math.sqrt((kp + 4 * chain.coupling_stiffness) / m)
    horizon = min(float(far_wait.min()) if far_wait.size else math.inf,
                  200 * 2 * math.pi / math.sqrt(kp / m))
    if horizon <= 0:  # a held block is at its limit already: it joins before anything moves
        return (0.0, np.zeros(count, bool), far_index[far_wait <= 0], x[slipping].copy(), v[slipping].copy(), 0.0)
    friction = W * chain.kinetic_friction * direction[slipping]
    work_x, work_v = x.copy(), v.copy()

    last = [None, None, None]  # scipy evaluates every event at one (tau, y) in turn: the forces are kept for them

    def forces(tau, y):
        if tau == last[0] and np.array_equal(y, last[1]):
            return last[2]
        work_x[slipping], work_v[slipping] = y[:count], y[count:]
        last[:] = tau, y.copy(), chain.forces(work_x, work_v, t0 + tau)
        return last[2]

    def rhs(tau, y):
        return np.concatenate([y[count:], (forces(tau, y)[slipping] - friction) / m])

    def stop(row):
        def event(tau, y):
            return y[count + row] * direction[slipping[row]] if tau > 0 else 1.0
        event.terminal, event.direction = True, -1
        return event

    def join(block):
        def event(tau, y):
            return limits[block] - abs(forces(tau, y)[block])
        event.terminal, event.direction = True, -1
        return event

    # A speed may dip below zero, or a headroom below its limit, and come back within one step: the sign test at
    # step ends misses it (as the closed form's grid did, issue 69). Each one's least value along the slip, where its
    # rate crosses zero upwards, is located too, and one at or below zero is a change the steps passed over.
    def slowest(row):  # d/dtau of a speed along its slip: the acceleration along it
        def event(tau, y):
            return (forces(tau, y)[slipping[row]] - friction[row]) * direction[slipping[row]]
        event.direction = 1
        return event

    rows = {block: row for row, block in enumerate(slipping)}
    neighbours = [[rows[other] for other in (block - 1, block + 1) if other in rows] for block in near_index]

    def tightest(which, block):  # d/dtau of W mu_s - |F|: F's rate is k_p V + k_c (its slipping neighbours' speeds)
        def event(tau, y):
            rate = kp * V + chain.coupling_stiffness * sum(y[count + row] for row in neighbours[which])
            return -math.copysign(1.0, forces(tau, y)[block]) * rate
        event.direction = 1
        return event

    changes = [stop(row) for row in range(count)] + [join(block) for block in near_index]
    least = [slowest(row) for row in range(count)] + [tightest(k, block) for k, block in enumerate(near_index)]
    options = dict(method=solver, rtol=rtol, atol=1e-14 * max(1.0, float(np.abs(x).max())),
                   max_step=2 * math.pi / omega / steps_per_period if steps_per_period else np.inf)
    solution = solve_ivp(rhs, (0.0, horizon), np.concatenate([x[slipping], v[slipping]]), events=changes + least,
                         first_step=min(horizon, 1e-3 * 2 * math.pi / omega), **options)

    def again(start, state, until):  # the stretch a change was passed over in, with its interpolant (rarely needed)
        return solve_ivp(rhs, (start, until), state, dense_output=True, **options).sol
    if solution.status < 0:
        raise SolverError(f"the chain: {solver} failed in a slip of {count} block(s) at t = {t0:.6g} s "
                          f"({solution.message}); use slip_solver = \"closed_form\", which is exact")
    tau = float(solution.t[-1])
    y = solution.y[:, -1]
    if solution.status == 0 and tau < horizon * (1 - 1e-12):
        raise SolverError(f"the chain: a slip of {count} block(s) from t = {t0:.6g} s did not end within "
                          f"{horizon:.3g} s; use slip_solver = \"closed_form\"")
    hit = [k for k, times in enumerate(solution.t_events[:len(changes)]) if times.size]
    missed = _passed_over(solution, changes, y, hit, again)
    if missed is not None:
        tau, hit, y = missed
    stops = np.zeros(count, bool)
    joins = []
    for k in hit:
        if k < count:
            stops[k] = True
        else:
            joins.append(int(near_index[k - count]))
    if far_index.size:
        joins.extend(far_index[far_wait <= tau * (1 + TOGETHER)].tolist())
    before = solution.t <= tau
    fastest = max(float(np.abs(solution.y[count:, before]).max(initial=0.0)), float(np.abs(y[count:]).max()))
    return tau, stops, np.unique(np.array(joins, int)), y[:count], y[count:], fastest


def _passed_over(solution, changes, end_state, hit, again):
    """The changes the steps passed over before the sub-phase's end: (the first one's time, the events within
    TOGETHER of it, the state there), or None. A change's function (a speed along its slip, or a headroom) is at or
    below zero at a located least value before the end, or at the end itself where its least lies beyond the
    terminal event in the same step; the crossing lies between that step's start, where the function was positive,
    and there, on the stretch integrated ``again`` from the step's start with its interpolant."""
    from scipy.optimize import brentq  # heavy: imported where used

    end = float(solution.t[-1])
    found = []
    for k, (change, times, states) in enumerate(zip(changes, solution.t_events[len(changes):],
                                                    solution.y_events[len(changes):])):
        if k in hit:
            continue
        for when, state in [*zip(times[times < end], states[times < end]), (end, end_state)]:
            if change(when, state) > 0.0:
                continue
            step = max(int(np.searchsorted(solution.t, when)) - 1, 0)
            start = float(solution.t[step])
            if start < when:
                interpolant = again(start, solution.y[:, step], when)

                def along(tau, change=change, interpolant=interpolant):
                    return change(tau, interpolant(tau))
                if along(when) > 0.0:  # integrated again, the least value stays above zero by round-off
                    root = when
                elif along(start) <= 0.0:  # at the step's start already (a change at its very beginning)
                    root = start
                else:
                    root = brentq(along, start, when, rtol=4 * np.finfo(float).eps, xtol=1e-13 * max(when, 1e-300))
            else:
                root, interpolant = when, None
            found.append((float(root), k, interpolant))
            break
    if not found:
        return None
    first, _, interpolant = min(found, key=lambda item: item[0])
    together = [k for root, k, _ in found if root <= first * (1 + TOGETHER)]
    if end <= first * (1 + TOGETHER):
        together.extend(hit)
    return first, together, (interpolant(first) if interpolant is not None else end_state)


def _off_zero(function, low: float, high: float):
    """A point just after ``low`` where ``function`` is positive (a block starting from rest speeds up first),
    or None if none is found before ``high`` (the slip ends within the first grid step)."""
    width = high - low
    for power in range(1, 40):
        trial = low + width * 2.0 ** -power
        if function(trial) > 0.0:
            return trial
    return None
