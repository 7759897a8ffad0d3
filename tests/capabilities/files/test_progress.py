"""Progress through one library (tqdm): a bar on a terminal, log lines when redirected, callables kept."""

from __future__ import annotations

import io

import pytest

from faultslip.io.progress import Progress, reporter


def test_redirected_progress_is_plain_log_lines_and_a_last_one():
    stream = io.StringIO()
    bar = Progress("sweep", "chunk", delay=0, interval=0, stream=stream)
    for done in range(1, 6):
        bar(done, 5)
    lines = stream.getvalue().splitlines()
    assert lines and "\r" not in stream.getvalue()
    assert all(line.split(" ", 1)[1].startswith("sweep") for line in lines)
    assert "5/5" in lines[-1] and bar.bar is None  # closed at the end


def test_quick_work_prints_nothing():
    stream = io.StringIO()
    bar = Progress("cycles", delay=60, interval=0, stream=stream)
    for done in range(1, 4):
        bar(done, 3)
    assert stream.getvalue() == ""


def test_a_callable_is_kept_and_silence_is_none():
    seen = []
    assert reporter(None, "x") is None and reporter(False, "x") is None
    callback = reporter(lambda done, total: seen.append((done, total)), "x")
    callback(1, 2)
    assert seen == [(1, 2)]
    assert isinstance(reporter(True, "x"), Progress)
    with pytest.raises(TypeError, match="progress must be"):
        reporter("yes", "x")


def test_long_library_work_reports_through_the_callable():
    from faultslip.dynamics.rate_state.slider import fault_cycles
    from faultslip.models.rate_state_slider.scene import read_rate_state_scene
    from pathlib import Path

    scene = read_rate_state_scene(Path(__file__).resolve().parents[3] / "configs" / "rsf_block_bp1.toml")
    seen = []
    fault_cycles(scene.slider, scene.plate_rate, cycles=2, progress=lambda done, total: seen.append((done, total)))
    # spin-up until the sequence settles, 2 measured, and the start of the next: the count reaches the total
    done, totals = zip(*seen)
    assert list(done) == list(range(1, len(seen) + 1)) and totals[-1] == done[-1] >= 5
    assert list(totals) == sorted(totals)
