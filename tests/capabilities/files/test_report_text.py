"""Reports that read well (issue 70): units by magnitude, no note twice, intervals that show their width."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from faultslip.io.report import LINE_WIDTH, Report


def test_a_second_unit_is_shown_only_where_it_reads_without_an_exponent():
    report = Report("t")
    report.add("lab_speed", 1e-6, "m/s", also=("mm/yr",))  # 1 um/s; as 31557.6 mm/yr it would not read
    report.add("plate_rate", 1e-9, "m/s", also=("in/yr",))  # 31.557 mm/yr, and 1.2424 in/yr reads
    text = report.to_text()
    assert "1 µm/s" in text and "31557" not in text
    assert "31.558 mm/yr  (1.2424 in/yr)" in text  # 1e-9 m/s over a Julian year: 31.5576 mm


def test_a_note_made_twice_is_printed_once():
    report = Report("t").note("the same sentence").note("another").note("the same sentence")
    assert report.notes == ["the same sentence", "another"]
    assert report.to_text().count("the same sentence") == 1


@settings(max_examples=200, deadline=None)
@given(st.floats(1e-6, 1e6), st.floats(1e-12, 1e-3))
def test_an_interval_of_different_ends_never_prints_two_equal_ends(low, relative_width):
    high = low * (1 + relative_width)
    if high == low:
        return
    report = Report("t")
    report.add("interval", [low, high], label="an interval")
    shown = report.to_text().splitlines()[-1].split("[")[1].rstrip("]").split(", ")
    assert shown[0] != shown[1], shown


def test_the_corner_plot_labels_every_parameter_a_fit_can_have():
    """A posterior with --detrend fitted carries 'trend' (and --stiffness-free 'stiffness'): the corner plot
    once raised KeyError for them (found by running the documented raw-record command on a fresh install)."""
    from types import SimpleNamespace

    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from faultslip.plots.posterior import corner_figure

    names = ["a", "b", "critical_slip", "trend", "stiffness", "a_new_parameter"]
    samples = np.random.default_rng(0).normal(1.0, 0.1, size=(200, len(names)))
    posterior = SimpleNamespace(names=names, samples=samples, walkers=32, r_hat={n: 1.001 for n in names},
                                effective_sample_size={n: 900.0 for n in names},
                                intervals=lambda: {n: (0.9, 1.1) for n in names})
    figure = corner_figure(posterior)
    labels = {axis.get_xlabel() for axis in figure.axes} | {axis.get_ylabel() for axis in figure.axes}
    assert r"$c$ (1/mm)" in labels and r"$k$ (1/mm)" in labels and "a new parameter" in labels


def test_a_long_title_is_folded_and_its_rule_is_as_long_as_its_longest_line():
    """An escalation's estimate was titled with its whole description: one line of 400 characters, and a rule
    of '=' as long."""
    title = "faultslip estimate: " + "the one slider, then the 2-D fault of the same scene; " * 8
    lines = Report(title).to_text().splitlines()
    rule = next(i for i, line in enumerate(lines) if set(line) == {"="})
    assert rule > 1 and all(len(line) <= LINE_WIDTH for line in lines)
    assert len(lines[rule]) == max(len(line) for line in lines[:rule])
    assert " ".join(lines[:rule]) == title.strip()
