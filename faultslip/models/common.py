"""What the model families share."""

from __future__ import annotations


def note_origin(report, origin) -> None:
    """Say first where a bundled scene came from (``origin`` is empty for a user's own file)."""
    if origin:
        report.notes.insert(0, f"scene: {origin}")


def note_scene(report, notes: dict) -> None:
    """Put a scene's origin and description first among the report's notes (where a loader gave them)."""
    for key in ("origin", "description"):
        if notes.get(key):
            report.notes.insert(0, notes[key])
