"""Figures of a spring-block chain: where each event slipped, its magnitude-frequency distribution with the
fitted Gutenberg-Richter line, and the intervals between system-size events."""

from __future__ import annotations

import numpy as np

from faultslip.models.spring_chain.dynamics import slipped_extents
from faultslip.plots.figures import _pyplot


def chain_figure(catalogue, stats: dict, title: str = ""):
    """Three panels: the events in block and time (each a bar from its first to its last block), the
    cumulative number N(>= M) against M with Aki's b-value line, and the system-size intervals.

    Parameters
    ----------
    catalogue : xarray.Dataset
        A chain's catalogue (:func:`faultslip.models.spring_chain.family.run`'s dataset).
    stats : dict
        Its statistics (b-value, system-size recurrence).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (events, frequency, intervals) = plt.subplots(1, 3, figsize=(12.5, 4.2), constrained_layout=True)
    start = catalogue["event_start"].values
    slip = catalogue["slip"].values
    first, last = slipped_extents(slip)
    scale, unit = (365.25 * 86400.0, "yr") if start.size and start[-1] > 3e7 else (1.0, "s")
    events.vlines(start / scale, first - 0.4, last + 0.4, color="C3", lw=0.8)
    events.set(xlabel=f"time ({unit})", ylabel="block", title="events: the blocks each slipped")
    magnitude = np.sort(catalogue["magnitude"].values)
    count = np.arange(magnitude.size, 0, -1)
    frequency.semilogy(magnitude, count, ".", ms=3, color="C0", label="N(>= M)")
    b = stats.get("b")
    if b is not None:
        line = np.linspace(b["completeness"], magnitude.max(), 50)
        frequency.semilogy(line, 10 ** (b["a"] - b["b"] * line), color="C3",
                           label=f"b = {b['b']:.2f} ({b['interval'][0]:.2f}-{b['interval'][1]:.2f})"
                           + (f", GR test p = {stats['gr']['p_value']:.2g}" if stats.get("gr") else ""))
    frequency.set(xlabel="moment magnitude M", ylabel="number of events with magnitude >= M",
                  title="magnitude-frequency")
    frequency.legend(fontsize=8)
    system = catalogue["blocks_slipped"].values >= stats.get("system_fraction", 0.5) * slip.shape[1]
    gaps = np.diff(start[system]) / scale
    if gaps.size:
        intervals.hist(gaps, bins=min(30, max(5, gaps.size // 3)), color="C2")
    intervals.set(xlabel=f"interval between system-size events ({unit})", ylabel="count",
                  title=f"recurrence (CV {stats.get('recurrence_cv', float('nan')):.2f})")
    if title:
        figure.suptitle(title)
    return figure


def chain_animation(run, frames: int = 120, title: str = ""):
    """A chain's events one a frame: each block's force against its static limit just after the event (the blocks
    that slipped in red), and the catalogue growing beneath it (the event's blocks against time).

    Parameters
    ----------
    run : ChainRun
        The chain's run.
    frames : int
        At most this many frames: the last events, one each.
    title : str
        The figure's title.

    Returns
    -------
    tuple
        (movie, figure): :func:`faultslip.plots.animation.save_gif` writes the movie.
    """
    from matplotlib import animation as mpl_animation  # heavy: imported where used

    plt = _pyplot()
    chain = run.chain
    count = min(frames, run.events)
    first = run.events - count
    # each block's position after every event, and its force then (held: v = 0, at the event's end)
    positions = run.final_position - np.cumsum(run.slip[::-1], axis=0)[::-1] + run.slip
    limits = chain.normal_load * chain.static_friction
    blocks = np.arange(chain.blocks)
    scale, unit = (365.25 * 86400.0, "yr") if run.end[-1] > 3e7 else (1.0, "s")
    figure, (state, catalogue) = plt.subplots(2, 1, figsize=(8, 6), constrained_layout=True,
                                              gridspec_kw={"height_ratios": [1, 1.2]})
    bars = state.bar(blocks, np.zeros(chain.blocks), color="C0", width=0.8)
    state.set(xlim=(-0.5, chain.blocks - 0.5), ylim=(min(-0.2, float(chain.kinetic_friction / chain.static_friction.max()
                                                                        - 1)), 1.3),  # room for the status line
              xlabel="block", ylabel="force / its static limit", title="the blocks after each event (red: slipped)")
    state.axhline(1.0, color="C3", lw=0.8, ls="--")
    slipped_start = run.start[first:] / scale
    low, high = slipped_extents(run.slip[first:])
    catalogue.vlines(slipped_start, low - 0.4, high + 0.4, color="0.8", lw=1.2)
    growing = catalogue.vlines([], [], [], color="C3", lw=1.5)
    current = catalogue.vlines([], [], [], color="k", lw=3)
    catalogue.set(xlim=(slipped_start[0], slipped_start[-1] + 1e-12), ylim=(-0.5, chain.blocks - 0.5),
                  xlabel=f"time ({unit})", ylabel="block", title="the catalogue")
    catalogue.ticklabel_format(axis="x", useOffset=False)
    status = state.text(0.01, 0.95, "", transform=state.transAxes, fontsize=8, va="top")
    figure.suptitle(title or chain.name, fontsize=9)

    def draw(index):
        event = first + index
        force = chain.forces(positions[event], np.zeros(chain.blocks), run.end[event])
        for block, bar in enumerate(bars):
            bar.set_height(force[block] / limits[block])
            bar.set_color("C3" if run.slip[event, block] != 0 else "C0")
        growing.set_segments([[(t, a - 0.4), (t, b + 0.4)] for t, a, b in
                              zip(slipped_start[:index + 1], low[:index + 1], high[:index + 1])])
        current.set_segments([[(slipped_start[index], low[index] - 0.4), (slipped_start[index], high[index] + 0.4)]])
        status.set_text(f"event {event + 1}: {int(run.blocks_slipped[event])} blocks, t = "
                        f"{run.start[event] / scale:.5g} {unit}")
        return [*bars, growing, current, status]

    movie = mpl_animation.FuncAnimation(figure, draw, frames=count, blit=False)
    movie.faultslip_frames = (draw, count)  # save_gif renders them itself (one draw a frame)
    return movie, figure
