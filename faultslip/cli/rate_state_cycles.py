"""faultslip rate-state cycles: a fault's quasi-dynamic earthquake cycles on one spring-block.

Its own module so that the command, often one short process, imports only the cycles' model
(:mod:`faultslip.models.rate_state_slider.cycles`), not every rate-and-state command's; ``--seed-law``, which needs
the seed law's fault scaling, is routed by the parser to ``faultslip.cli.rate_state``.
"""

from __future__ import annotations

import faultslip
from faultslip.cli.printing import _emit, _progress


def cmd_cycles(args) -> int:
    return _emit(faultslip.models.earthquake_cycles(args.scene, args.cycles,
                                   progress=_progress("cycles", not args.json, "event")).report(), args.json)
