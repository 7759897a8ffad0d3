"""The constant-friction family's figure: the sawtooth of the spring force."""

from __future__ import annotations


def sawtooth_figure(time, ratio):
    """Spring force / W against time."""
    import matplotlib.pyplot as plt  # heavy: imported where used

    fig, ax = plt.subplots()
    ax.plot(time, ratio)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("spring force / W")
    return fig
