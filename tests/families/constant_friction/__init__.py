"""A test family: a spring-slider with constant static and kinetic friction (no rate effect, no damping).

It is the proof that a family is one folder and one registry line (issue 40): ``tests/capabilities/contract/test_families.py``
declares it with :func:`faultslip.contract.declare`, and run, simulate, sweep, the CLI and the conformance
check take it with no edit anywhere in faultslip. Its physics is the undamped slider's exact cycle: the spring
loads to mu_s W, the block slides half an oscillation to the symmetric point about mu_k W, so

    slip per event = 2 (mu_s - mu_k) W / K,   recurrence = slip / V (the stick lasts slip / V, the slip pi / omega).

::

    family = "constant_friction"
    [slider]
    stiffness = "1e5 N/m"
    normal_load = "100 N"
    mass = "1 kg"
    platform_speed = "1 mm/s"
    [friction]
    static = 0.6
    kinetic = 0.5

The folder is the family: ``scene`` (its reader, parameters and outputs), ``family`` (the declaration, run,
simulate, methods and sweep) and ``figures``.
"""
