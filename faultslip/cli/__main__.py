"""``python -m faultslip.cli``: the faultslip program."""

from faultslip.cli.main import console

console()
