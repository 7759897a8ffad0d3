"""Apps served to a browser: classroom."""

from __future__ import annotations

import sys

from faultslip.apps.classroom import check_address, serve
from faultslip.apps.lesson import export_lesson
from faultslip.cli.common import _locked, _outputs
from faultslip.errors import FaultslipError


def cmd_classroom(args) -> int:
    if args.export is not None:  # the lesson as one file: nothing is served
        output = _outputs(args, {"export": ("--export", (".html",))})["export"]
        with _locked(output):
            size = export_lesson(output)
        print(f"faultslip classroom: wrote {args.export} ({size / 1e6:.2f} MB), a lesson that opens offline in any "
              "browser")
        return 0
    if not 1 <= args.port <= 65535:
        raise FaultslipError(f"--port must be from 1 to 65535, got {args.port}")
    check_address(args.address)  # before anything starts

    def announce(url):
        print(f"faultslip classroom: open {url} in a browser (Ctrl-C stops it)", flush=True)

    try:
        serve(port=args.port, address=args.address, open_browser=args.open, announce=announce)
    except OSError as exc:
        raise FaultslipError(f"cannot serve on {args.address}:{args.port}: {exc.strerror or exc}") from None
    except KeyboardInterrupt:
        print("faultslip classroom: stopped", file=sys.stderr)
    return 0
