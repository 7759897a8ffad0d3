"""Counting what a library function finds while a benchmark runs (the searches for events passed over)."""

from __future__ import annotations

import contextlib


@contextlib.contextmanager
def found_by(module, name: str):
    """Within the block, ``module.name`` is wrapped so that each call returning something other than None is counted;
    yields a one-element list holding the count. The original is restored on leaving."""
    found, original = [0], getattr(module, name)

    def counting(*args, **kwargs):
        result = original(*args, **kwargs)
        found[0] += result is not None
        return result

    setattr(module, name, counting)
    try:
        yield found
    finally:
        setattr(module, name, original)
