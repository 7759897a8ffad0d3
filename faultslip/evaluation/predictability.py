"""A catalogue's recurrence models tested, as students test them (``faultslip predictability``; issue 45).

The events come from a QuakeML or CSV catalogue read through obspy (:func:`faultslip.io.catalogs.read_catalog`),
optionally those whose name holds a text (``Parkfield``). A catalogue gives magnitudes, not slips: on one fault
patch the seismic moment M0 = 10^(1.5 Mw + 9.1) N m is proportional to the slip (M0 = G A s, Hanks & Kanamori
1979), so the moment stands for it, and the correlations, which do not depend on the unit, test the same models.
"""

from __future__ import annotations

import numpy as np

from faultslip.errors import InputError
from faultslip.fault.predictability import Predictability, predictability
from faultslip.io.catalogs import read_catalog


def catalog_predictability(path, name: str | None = None, seed: int = 0) -> Predictability:
    """The time-predictable, slip-predictable, periodic and Poisson models tested on a catalogue's events.

    Parameters
    ----------
    path : str or path
        A QuakeML or CSV catalogue (``configs/catalog_san_andreas.csv``).
    name : str, optional
        Keep the events whose name holds this text (``"Parkfield"``), ignoring case.
    seed : int
        The bootstrap's seed.

    Returns
    -------
    Predictability
        With the seismic moment (N m) standing for each event's slip.
    """
    catalog = read_catalog(path)
    keep = np.array([name is None or name.lower() in str(label).lower() for label in catalog.name], bool)
    if not keep.any():
        raise InputError(f"no event of {path} has {name!r} in its name")
    times = catalog.time[keep].astype("datetime64[ms]").astype(np.int64) / 1e3
    moments = 10.0 ** (1.5 * catalog.magnitude[keep] + 9.1)
    return predictability(times, moments, seed=seed, slip_unit="N m (seismic moment, proportional to slip)")
