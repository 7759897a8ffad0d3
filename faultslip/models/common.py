"""What the model families share."""

from __future__ import annotations


def note_origin(report, origin) -> None:
    """Say first where a bundled scene came from (``origin`` is empty for a user's own file)."""
    if origin:
        report.notes.insert(0, f"scene: {origin}")
