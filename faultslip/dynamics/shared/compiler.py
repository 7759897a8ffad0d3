"""Whether numba, the optional compiler (``pip install faultslip[fast]``), is here: probed once."""

from __future__ import annotations

_AVAILABLE = []


def available() -> bool:
    """Whether numba imports here, so that a compiled kernel can be used (probed once)."""
    if not _AVAILABLE:
        try:
            import numba  # noqa: F401  heavy: optional dependency (faultslip[fast]), only probed
        except ImportError:
            _AVAILABLE.append(False)
        else:
            _AVAILABLE.append(True)
    return _AVAILABLE[0]
