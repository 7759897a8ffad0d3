"""A plane-strain run's SEAS BP3 files and netCDF variables.

BP3 (Erickson, Jiang & Dunham 2021, sec. 4) asks for on-fault stations with the normal stress, surface stations
(horizontal and vertical displacement and velocity), and slip, shear-stress and normal-stress profiles about
500 m apart down dip. Its signs are physical: a normal fault's slip, slip rate and shear stress are negative, and
so are its surface motions against a thrust's; the run keeps slip positive in the fault's own sense, and these
writers turn it.

The stress profiles are computed from the recorded slip profiles with the run's own kernels (tau = tau_0 +
K_shear (delta - V_p t) - eta V, sigma_n = sigma_n0 + K_normal (delta - V_p t)), a block of rows at a time.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from faultslip.io.seas import (station_file_name, surface_file_name, write_profiles, write_station,
                               write_surface_station)
from faultslip.models.fault_2d.plane_strain import PlaneStrainOperator

#: BP3's profile spacing down dip (m).
PROFILE_SPACING = 500.0
PROBLEM = "SEAS Benchmark BP3-QD"


def sign(fault) -> float:
    """+1 for thrust, -1 for normal: BP3's sign of slip, slip rate, shear stress and the surface's motion."""
    return 1.0 if fault.sense == "thrust" else -1.0


def profile_elements(fault, spacing: float = PROFILE_SPACING) -> np.ndarray:
    """The elements nearest to 0, ``spacing``, 2 ``spacing``, ... down the fault (each once)."""
    wanted = np.arange(0.0, fault.width + spacing / 2, spacing)
    return np.unique(np.clip(np.round(wanted / fault.element_size - 0.5), 0, fault.count - 1).astype(int))


class _StressRows:
    """Rows of a stress profile, computed from the slip profiles when sliced (a block at a time)."""

    def __init__(self, run, elements: np.ndarray, normal: bool):
        fault = run.fault
        operator = PlaneStrainOperator(fault)
        rows = slice(fault.count, None) if normal else slice(0, fault.count)
        self.matrix = operator.matrix[rows][elements]
        self.base = (fault.normal_stress if normal else fault.initial_shear_stress)[elements]
        self.damping = 0.0 if normal else fault.damping
        self.run, self.elements, self.scale = run, elements, (1.0 if normal else sign(fault)) / 1e6

    def __getitem__(self, rows: slice) -> np.ndarray:
        run = self.run
        slip = np.asarray(run.profiles[rows], float)
        time = np.asarray(run.profile_time[rows], float)
        deficit = slip - run.fault.plate_rate * time[:, None]
        stress = self.base + deficit @ self.matrix.T
        if self.damping:
            stress = stress - self.damping * 10.0 ** np.asarray(run.profile_log10_slip_rate[rows], float)[:, self.elements]
        return stress * self.scale


class _SlipRows:
    def __init__(self, run, elements: np.ndarray):
        self.run, self.elements, self.sign = run, elements, sign(run.fault)

    def __getitem__(self, rows: slice) -> np.ndarray:
        return self.sign * np.asarray(self.run.profiles[rows], float)[:, self.elements]


def write_bp3(run, folder: Path, version: str, name: str) -> None:
    """BP3's files for ``run`` in ``folder``: ``fltst_dpXXX`` (with the normal stress), ``srfst_fn±XX``, and
    ``slip.dat``, ``shear_stress.dat`` and ``normal_stress.dat``; each atomic."""
    fault = run.fault
    turn = sign(fault)
    problem = f"{PROBLEM} ({name})"
    extras = run.plane_strain
    for k, distance in enumerate(run.station_depths):
        write_station(folder / station_file_name(distance), run.station_time, turn * run.stations["slip"][:, k],
                      run.stations["log10_slip_rate"][:, k], turn * run.stations["shear_stress"][:, k] / 1e6,
                      run.stations["log10_state"][:, k], depth=float(distance), element_size=fault.element_size,
                      version=version, problem=problem, normal_stress_mpa=extras["normal_stress"][:, k] / 1e6)
    for k, position in enumerate(extras["surface_positions"]):
        write_surface_station(folder / surface_file_name(position), run.station_time,
                              turn * extras["surface_displacement"][:, :, k],
                              turn * extras["surface_velocity"][:, :, k], position=float(position),
                              element_size=fault.element_size, version=version, problem=problem)
    elements = profile_elements(fault)
    for quantity, rows in (("slip", _SlipRows(run, elements)), ("shear_stress", _StressRows(run, elements, False)),
                           ("normal_stress", _StressRows(run, elements, True))):
        write_profiles(folder / f"{quantity}.dat", run.profile_time, run.profile_max_speed, rows,
                       fault.depth[elements], element_size=fault.element_size, version=version, problem=problem,
                       quantity=quantity, down_dip=True)


def dataset_variables(run) -> tuple[dict, dict, dict]:
    """(data variables, coordinates, attributes) a plane-strain run adds to its netCDF: the stations' normal
    stress and the surface's displacement and velocity, in BP3's signs."""
    fault, extras = run.fault, run.plane_strain
    turn = sign(fault)
    data = {
        "station_normal_stress": (("time", "station"), np.asarray(extras["normal_stress"]),
                                  {"units": "Pa", "long_name": "effective normal stress (compression positive)"}),
        "surface_displacement": (("time", "component", "surface"), turn * extras["surface_displacement"],
                                 {"units": "m", "long_name": "surface displacement (BP3 signs; vertical positive down)"}),
        "surface_velocity": (("time", "component", "surface"), turn * extras["surface_velocity"],
                             {"units": "m/s", "long_name": "surface velocity (BP3 signs; vertical positive down)"}),
        "true_depth": ("depth", fault.true_depth, {"units": "m", "long_name": "depth of the element centre below the "
                                                                           "surface", "positive": "down"}),
    }
    coords = {"surface": ("surface", extras["surface_positions"],
                          {"units": "m", "long_name": "distance from the trace, positive over the hanging wall"}),
              "component": ("component", np.array(["horizontal", "vertical"]))}
    attrs = {"plane": fault.plane, "dip_degree": fault.dip, "sense": fault.sense, "poisson_ratio": fault.poisson_ratio}
    return data, coords, attrs
