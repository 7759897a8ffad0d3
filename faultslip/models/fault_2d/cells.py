"""The 2-D fault family's sweep: one checkpointed run per cell, resumable where a study stopped."""

from __future__ import annotations

import hashlib
import itertools
import math
from pathlib import Path

import numpy as np

from faultslip.contract.cells import evaluate_by_cell
from faultslip.contract.specs import Output, parameters
from faultslip.models.fault_2d.analysis import summarise
from faultslip.errors import InputError
from faultslip.models.fault_2d.scene import SWEEPABLE, parse_fault_2d_scene

PARAMETERS = parameters(SWEEPABLE)

#: A 2-D fault cell's outputs.
OUTPUTS = {spec.name: spec for spec in (
    Output("recurrence_interval", "s", "mean interval between system-size events over a supercycle, an aperiodic "
                                       "run, or an unsettled run's intervals after the first (NaN with fewer than "
                                       "two events)"),
    Output("recurrence_spread", "1", "largest change of an interval over a supercycle (periodic), the intervals' "
                                     "coefficient of variation (aperiodic), or their largest deviation about the "
                                     "mean (unsettled)"),
    Output("settled", "1", "1 where the sequence is periodic (any period up to 8, to 1e-3), 0 where it is not"),
    Output("period", "1", "events in the supercycle (1: every event alike; 0: aperiodic or unsettled)"),
    Output("slip_per_event", "m", "surface slip per system-size event closing the measured intervals"),
    Output("mean_slip_per_event", "m", "slip per system-size event closing the measured intervals, mean over the "
                                       "velocity-weakening width"),
    Output("moment_per_length", "N", "seismic moment per metre along strike per system-size event closing the "
                                     "measured intervals"),
    Output("events", "1", "events in the run (peak slip rate above 1e-3 m/s)"),
    Output("peak_slip_rate", "m/s", "largest slip rate in the run"),
    Output("nucleation_size", "m", "h* = (pi/2) G D_c b / (sigma_n (b - a)^2)"),
    Output("plate_slip_balance", "1", "slip per cycle at the shallowest station / (V_pl T)"),
    Output("steps", "1", "Dormand-Prince steps taken"),
)}


def fault_2d_cell_seconds(scene, dims: dict | None = None) -> float:
    """A 2-D fault cell's mean run time over the study's cells (each cell's own element size, D_c, V_pl...):
    :meth:`Fault2DScene.estimate`. A grid of more than 256 cells is estimated from its corners and centre."""
    dims = dims or {}
    names = list(dims)
    if not names:
        return scene.estimate().seconds
    axes = [np.asarray(dims[name], dtype=object if any(isinstance(v, str) for v in dims[name]) else float)
            for name in names]
    if int(np.prod([axis.size for axis in axes])) <= 256:
        cells = itertools.product(*axes)
    else:
        cells = itertools.product(*[np.unique(axis[[0, axis.size // 2, -1]]) for axis in axes])
    seconds = [scene.with_values(**dict(zip(names, (str(v) if isinstance(v, str) else float(v) for v in cell))))
               .estimate().seconds for cell in cells]
    return float(np.mean(seconds))


class Fault2DCells:
    """:class:`faultslip.contract.cells.Cells` of the 2-D fault: each cell checkpointed in ``study.work_dir``
    (a resumed study continues a cell where it stopped); a cell's result does not depend on its block or
    worker."""

    label = "a 2-D fault study"
    checkpoints = True
    default_tolerance = None

    def parameters(self, scene) -> dict:
        return PARAMETERS

    def category(self, scene, name: str, value: str, where: str) -> str:
        if name == "sense" and value in ("thrust", "normal"):
            return value
        raise InputError(f"{where}: a 2-D fault study sweeps numbers, and sense as thrust or normal; got {value!r}")

    def check(self, study, where: str, source: str) -> None:
        if study.method not in ("auto", "fault_2d") or study.cycles:
            raise InputError(f"{where} a 2-D fault study runs the 2-D model for the base scene's [run] duration; "
                             "leave method and cycles out")
        names = list(study.dims)
        corners = np.array(np.meshgrid(*[[0, len(v) - 1] for v in study.dims.values()], indexing="ij"))
        for index in corners.reshape(len(names), -1).T if names else [()]:  # L_b is monotone in each parameter
            cell = study.scene.with_values(**{name: study.dims[name][i] for name, i in zip(names, index)})
            cell.require_resolution()

    def outputs(self, study) -> dict:
        return OUTPUTS

    def attrs(self, name: str, study, flagged: bool = False) -> dict:
        return OUTPUTS[name].attrs()

    def seconds_per_cell(self, study) -> float:
        return fault_2d_cell_seconds(study.scene, study.dims)

    def seconds_per_worker(self, study) -> float:
        """A worker's first cell loads the compiled step, or compiles it where numba's cache has none
        (:meth:`Fault2DScene.first_run_cost` of a process that holds none yet)."""
        return study.scene.first_run_cost(fresh_process=True)[0]

    def counted(self, study) -> bool:
        return False  # no flags: settled and events are numbers

    def evaluate(self, study, values: dict) -> dict:

        def cell(**inputs):
            scene = study.scene.with_values(**inputs)
            folder = None
            if study.work_dir is not None:
                key = hashlib.sha256(repr(sorted((n, v if isinstance(v, str) else float(v))
                                                 for n, v in inputs.items())).encode()).hexdigest()[:16]
                folder = Path(study.work_dir) / key
            resume = folder is not None and (folder / "checkpoint.npz").is_file()
            run = scene.run(folder=folder, resume=resume)
            summary = summarise(run, unsettled_mean=True)  # read as faultslip.run reads the scene
            row = {"recurrence_interval": summary.recurrence_interval,
                   "recurrence_spread": summary.recurrence_spread, "settled": float(summary.settled),
                   "period": float(summary.sequence.period),
                   "slip_per_event": summary.surface_slip_per_event,
                   "mean_slip_per_event": summary.mean_slip_per_event,
                   "moment_per_length": summary.moment_per_length, "events": float(summary.events),
                   "peak_slip_rate": summary.peak_slip_rate, "nucleation_size": scene.fault.nucleation_size(),
                   "plate_slip_balance": summary.plate_slip_balance_surface, "steps": float(run.steps)}
            return {name: value if value is not None and math.isfinite(value) else np.nan
                    for name, value in row.items()}

        return evaluate_by_cell(values, OUTPUTS, cell)


CELLS = Fault2DCells()


def read_scene(text: str, source: str, path=None):
    """A 2-D fault scene file, as a study's base."""
    scene = parse_fault_2d_scene(text, source)
    scene.path = path
    return scene
