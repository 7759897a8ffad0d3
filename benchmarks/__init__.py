"""faultslip's benchmarks: each a script (``python benchmarks/NAME.py``), all behind one entry point
(``python -m benchmarks NAME [ARGS]``, ``python -m benchmarks --all --quick``); see ``__main__``."""
