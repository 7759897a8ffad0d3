"""What the model families share."""

from __future__ import annotations


def note_origin(report, text) -> None:
    """Say where a bundled scene came from (nothing for a user's file)."""
    if text:
        report.note(text)
