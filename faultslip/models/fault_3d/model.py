"""The 3-D fault: a planar fault in a half-space cut into squares along strike and down dip, with the 2-D fault's
force balance, friction and state on every square (SEAS BP5-QD, Jiang et al. 2022, JGR 127, e2021JB023519).

The fault is :class:`faultslip.models.fault_2d.model.Fault2D`'s arrays, one value per square, square (i, j) (i along
strike, j down dip) at index i N_z + j; the 2-D fault's stepping, records and checkpoints run it
(:func:`faultslip.models.fault_2d.integrate.run_cycles`) with the traction operator of
:mod:`faultslip.models.fault_3d.kernel`. Outside the squares the fault slips steadily at the plate rate, so the
stress is K (delta - V_p t) as on the 2-D fault: slip at V_p over the whole plane is a rigid motion.

The rake is held fixed (slip along strike, or up or down dip): the one slip component BP5's loading drives. BP5's
participants solve two components; the second, down dip on a strike-slip fault, is driven only by the
dislocations' traction across the rake near the patch's edges, and a run reports it against the traction along
the rake (``cross_rake_traction_share``, from its last system-size event's slip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultslip.errors import InputError
from faultslip.fault.ladder import FaultDescription
from faultslip.models.fault_2d.model import Fault2D
from faultslip.models.fault_3d.kernel import RAKES


@dataclass
class Fault3D(Fault2D):
    """A planar fault of ``strike_count`` x N_z squares of side ``element_size``; the first square's up-dip edge
    starts ``strike_origin`` along strike (m; BP5 centres the fault on 0). Arrays hold one value per square, square
    (i, j) at i N_z + j; :attr:`depth` is each square's distance down dip, :attr:`strike_position` its centre along
    strike. ``rake``: "strike", "thrust" or "normal"."""

    strike_count: int = 2
    strike_origin: float = 0.0
    rake: str = "strike"

    PLANES = ("3d",)
    KIND = "3-D fault"

    def __post_init__(self):
        super().__post_init__()
        if not (isinstance(self.strike_count, (int, np.integer)) and self.strike_count >= 2
                and self.count % self.strike_count == 0 and self.count // self.strike_count >= 2):
            raise InputError(f"3-D fault: {self.count} squares do not make {self.strike_count!r} columns of 2 or more "
                             "down dip")
        if self.rake not in RAKES:
            raise InputError(f"3-D fault: the rake must be one of {', '.join(RAKES)}, got {self.rake!r}")
        if not math.isfinite(self.strike_origin):
            raise InputError("3-D fault: strike_origin must be finite")

    @property
    def dip_count(self) -> int:
        return self.count // self.strike_count

    @property
    def width(self) -> float:
        """The fault's extent down dip (m)."""
        return self.dip_count * self.element_size

    @property
    def length(self) -> float:
        """The fault's extent along strike (m)."""
        return self.strike_count * self.element_size

    @property
    def depth(self) -> np.ndarray:
        """Each square's centre, down dip from the surface (m)."""
        return np.tile((np.arange(self.dip_count) + 0.5) * self.element_size, self.strike_count)

    @property
    def strike_position(self) -> np.ndarray:
        """Each square's centre along strike (m)."""
        return np.repeat(self.strike_origin + (np.arange(self.strike_count) + 0.5) * self.element_size,
                         self.dip_count)

    def grid(self, values: np.ndarray) -> np.ndarray:
        """``values`` (N, or rows x N) as (..., strike, down dip)."""
        values = np.asarray(values)
        return values.reshape(values.shape[:-1] + (self.strike_count, self.dip_count))

    def seismogenic_width(self) -> float:
        """The widest column's velocity-weakening extent down dip (m)."""
        return float(self.grid(self.b > self.a).sum(axis=-1).max() * self.element_size)

    def seismogenic_length(self) -> float:
        """The longest row's velocity-weakening extent along strike (m)."""
        return float(self.grid(self.b > self.a).sum(axis=-2).max() * self.element_size)

    def column(self, strike: float | None = None) -> int:
        """The column nearest ``strike`` (m; the middle where None)."""
        if strike is None:
            return self.strike_count // 2
        return int(np.clip(np.floor((strike - self.strike_origin) / self.element_size), 0, self.strike_count - 1))

    def description(self, strike: float | None = None) -> FaultDescription:
        """The column at ``strike`` (the middle one where None) as the 2-D rungs read a fault: the friction down dip,
        elasticity and loading (:class:`faultslip.fault.ladder.FaultDescription`)."""
        column = slice(self.column(strike) * self.dip_count, (self.column(strike) + 1) * self.dip_count)
        plane = "antiplane" if self.dip == 90.0 and self.rake == "strike" else "strain"
        sense = self.rake if self.rake in ("thrust", "normal") else "thrust"
        return FaultDescription((np.arange(self.dip_count) + 0.5) * self.element_size, self.a[column],
                                self.b[column], self.critical_slip[column], self.normal_stress[column],
                                self.element_size, self.shear_modulus, self.shear_wave_speed, self.plate_rate,
                                self.reference_speed, self.reference_friction, self.evolution, self.name, plane,
                                self.dip, sense, self.poisson_ratio)


class StationGrid:
    """Stations on a 3-D fault, each the bilinear interpolation of the four squares around it (clipped at the
    fault's edges): the recorder :func:`faultslip.models.fault_2d.integrate.run_cycles` takes.

    ``positions``: (along strike, down dip) pairs (m), in the fault's frame (:attr:`Fault3D.strike_origin`)."""

    def __init__(self, positions, fault: Fault3D):
        positions = np.asarray(positions, float).reshape(-1, 2)
        if positions.size == 0:
            raise InputError("a 3-D fault needs at least one station")
        along, down = positions[:, 0], positions[:, 1]
        low, high = fault.strike_origin, fault.strike_origin + fault.length
        if np.any(along < low) or np.any(along > high) or np.any(down < 0) or np.any(down > fault.width):
            raise InputError(f"stations must lie on the fault: along strike from {low / 1e3:g} to {high / 1e3:g} km, "
                             f"down dip from 0 to {fault.width / 1e3:g} km")
        self.positions = positions
        self.depths = down
        h = fault.element_size
        i = np.clip((along - low) / h - 0.5, 0.0, fault.strike_count - 1.0)
        j = np.clip(down / h - 0.5, 0.0, fault.dip_count - 1.0)
        i0 = np.minimum(np.floor(i).astype(int), fault.strike_count - 2)
        j0 = np.minimum(np.floor(j).astype(int), fault.dip_count - 2)
        wi, wj = i - i0, j - j0
        nz = fault.dip_count
        self.neighbours = np.concatenate([i0 * nz + j0, (i0 + 1) * nz + j0, i0 * nz + j0 + 1,
                                          (i0 + 1) * nz + j0 + 1])
        self.weights = np.stack([(1 - wi) * (1 - wj), wi * (1 - wj), (1 - wi) * wj, wi * wj])

    def __call__(self, values: np.ndarray) -> np.ndarray:
        return self.between(np.asarray(values)[self.neighbours])

    def between(self, at_neighbours: np.ndarray) -> np.ndarray:
        """The stations' values from a field's values at :attr:`neighbours`."""
        size = self.depths.size
        total = at_neighbours[:size] * self.weights[0]
        for k in range(1, len(self.weights)):
            total = total + at_neighbours[k * size:(k + 1) * size] * self.weights[k]
        return total


def bp5_initial_conditions(a, b, normal_stress, damping, initial_speed, state_speed, reference_speed,
                           reference_friction) -> tuple[np.ndarray, np.ndarray]:
    """(tau_0, psi_0) of SEAS BP5: the state of steady sliding at ``state_speed`` (theta_0 = D_c / V_init),
    psi_0 = f_0 + b ln(V_0 / V_init), and the shear stress that gives each square the slip rate
    ``initial_speed`` (V_init, or the nucleation patch's faster V_i) with its own a:

        tau_0 = sigma_n a asinh[V_i / (2 V_0) exp(psi_0 / a)] + eta V_i.
    """
    psi0 = reference_friction + b * np.log(reference_speed / state_speed)
    tau0 = normal_stress * a * np.arcsinh(initial_speed / (2 * reference_speed) * np.exp(psi0 / a)) \
        + damping * initial_speed
    return np.asarray(tau0, float), np.asarray(psi0, float) * np.ones_like(np.asarray(a, float))
