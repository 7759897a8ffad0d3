"""A 2-D fault: quasi-dynamic earthquake cycles on a vertical strike-slip fault in an elastic
half-space (antiplane), with rate-and-state friction varying in depth (SCEC SEAS BP1).

* ``kernel``: the antiplane stress of uniform-slip elements with the free-surface image, dense
  and as a Toeplitz-plus-Hankel product by FFT;
* ``model``: the fault's parameters in depth, its force balance and its rates;
* ``integrate``: adaptive Dormand-Prince 5(4) stepping with event detection, station, profile
  and event recording, checkpoints and bit-identical restart.
"""
