"""A test family for batch systems: the constant-friction slider, each cell taking ``FAULTSLIP_TEST_CELL_SECONDS``
and logging its start and end (with the SLURM job that ran it) to ``FAULTSLIP_TEST_CELL_LOG``, and failing where
its static friction exceeds ``FAULTSLIP_TEST_FAIL_ABOVE``. The tests of killed jobs, failure ledgers and
``--retry-failed`` count its cells by that log (tests/capabilities/studies/test_slurm.py)."""
