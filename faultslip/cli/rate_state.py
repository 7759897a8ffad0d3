"""Rate-and-state commands: simulate, stability, cycles (and fit --law rate-state in faultslip.cli.lab)."""

from __future__ import annotations

import faultslip
from faultslip.cli.common import _locked, _outputs
from faultslip.cli.printing import _emit, _progress
from faultslip.errors import FaultslipError
from faultslip.io.netcdf import write_dataset


def cmd_missing_action(args) -> int:
    raise FaultslipError("faultslip rate-state needs an action: simulate, stability, cycles or bench")


def cmd_simulate(args) -> int:
    output = _outputs(args, {"output": ("-o", (".nc",))}, [args.scene])["output"]
    result = faultslip.models.velocity_step(args.scene, method=args.method, rtol=args.rtol)
    report = result.report()
    if output:
        with _locked(output):
            write_dataset(result.time_series(), output)
        report.note(f"time series written to {output}")
    return _emit(report, args.json)


def cmd_stability(args) -> int:
    return _emit(faultslip.models.rate_state_stability(args.scene).report(), args.json)


def cmd_cycles_beside_seed_law(args) -> int:
    """rate-state cycles --seed-law: the cycles, and the seed law on the same fault (the parser routes here)."""
    return _emit(faultslip.models.earthquake_cycles_beside_seed_law(args.scene, args.cycles, args.seed_law,
                                   progress=_progress("cycles", not args.json, "event")).report(), args.json)
