"""The ``faultslip`` command line. Thin: it parses, calls the library, prints (see :mod:`faultslip.cli.main`)."""

from faultslip.cli.main import console, main

__all__ = ["console", "main"]
