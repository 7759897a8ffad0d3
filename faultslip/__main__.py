"""``python -m faultslip``: the faultslip program, where the ``faultslip`` script is not on the PATH."""

from faultslip.cli.main import console

console()
