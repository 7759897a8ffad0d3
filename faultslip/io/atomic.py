"""Atomic output: write to a temporary file in the target directory, then rename.

An interrupted run therefore leaves either nothing or the complete previous
file under the final name, never a truncated one.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from faultslip.errors import InputError


@contextlib.contextmanager
def atomic_path(path, suffix: str | None = None):
    """Yield a temporary path next to ``path``; on success rename it over ``path``.

    On any exception (including KeyboardInterrupt) the temporary file is
    removed and ``path`` is untouched.
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise InputError(f"output directory {str(directory)!r} does not exist")
    handle, temporary = tempfile.mkstemp(
        prefix=f".{target.name}.", suffix=suffix if suffix is not None else (target.suffix or ".tmp") + ".tmp", dir=directory
    )
    os.close(handle)
    try:
        yield Path(temporary)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes 0600; a normal file respects the umask
        os.replace(temporary, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)
        raise


def _umask() -> int:
    current = os.umask(0)
    os.umask(current)
    return current


def write_text_atomic(path, text: str) -> None:
    with atomic_path(path) as temporary:
        temporary.write_text(text, encoding="utf-8")


def save_figure(figure, path, **kwargs) -> None:
    """Save a matplotlib figure atomically; the format follows the file name."""
    target = Path(path)
    fmt = target.suffix.lstrip(".").lower() or "png"
    with atomic_path(target) as temporary:
        figure.savefig(temporary, format=fmt, **kwargs)
    import matplotlib.pyplot as plt  # heavy: matplotlib only once a figure exists

    plt.close(figure)  # a saved figure is done with; pyplot would otherwise keep every one open
