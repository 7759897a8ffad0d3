"""Bytes from a browser upload, handed to a reader that takes a path."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path


@contextlib.contextmanager
def scratch_copy(content: bytes, suffix: str = ""):
    """``content`` as a private temporary file (0600, in a fresh private folder), removed afterwards.

    The upload's own name never becomes a path: only its suffix is kept, so a name such as
    ``../../x`` or ``<img src=x>.csv`` touches nothing."""
    suffix = suffix if suffix in (".csv", ".txt") else ".csv"
    with tempfile.TemporaryDirectory(prefix="faultslip-") as folder:
        path = Path(folder) / f"upload{suffix}"
        descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
        with os.fdopen(descriptor, "wb") as handle:
            handle.write(content)
        yield path
