"""The stick-slip slider as an animation (``faultslip animate``): block, spring and moving platform beside
the phase-plane trajectory and the friction trace, all synchronised.

Seed 003's apparatus: a spring of stiffness K anchored on the left holds a block on a platform moving at
V; the block rides the platform while it sticks and slips back when the spring force reaches static
friction. Frames are spaced evenly in *warped* time: each slip phase gets ``slip_share`` of the frames
in proportion to its duration beside the sticks, so a fault's 20 s ruptures between century-long sticks
stay visible. The title states the compression: how much faster a stick plays than a slip.
"""

from __future__ import annotations

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip.errors import InputError
from faultslip.io.progress import reporter
from faultslip.io.atomic import save_frames
from faultslip.plots.figures import _pyplot

#: frames allowed in one GIF (a teacher's laptop, and file sizes of a few MB)
MAX_FRAMES = 2000


def frame_times(dataset, frames: int, slip_share: float = 0.5) -> tuple[np.ndarray, float]:
    """Times of the frames over the recorded cycles, and the compression (stick speed-up over slip speed-up).

    Slip phases take ``slip_share`` of the frames (or their true share, if that is larger), sticks the rest,
    each spread evenly in time within its kind."""
    if not 2 <= frames <= MAX_FRAMES:
        raise InputError(f"frames must be from 2 to {MAX_FRAMES}, got {frames}")
    if not 0 < slip_share < 1:
        raise InputError(f"slip_share must lie strictly between 0 and 1, got {slip_share}")
    time = dataset["time"].values
    slipping = dataset["phase"].values == 1
    steps = np.diff(time)
    slip_time = float(np.sum(steps[slipping[1:]]))
    stick_time = float(np.sum(steps[~slipping[1:]]))
    total = slip_time + stick_time
    if slip_time <= 0 or stick_time <= 0:  # one kind only: plain time
        return np.linspace(time[0], time[-1], frames), 1.0
    share = max(slip_share, slip_time / total)
    # warped clock: a slip second weighs share / slip_time, a stick second (1 - share) / stick_time
    weight = np.where(slipping[1:], share / slip_time, (1 - share) / stick_time)
    warped = np.concatenate([[0.0], np.cumsum(steps * weight)])
    targets = np.linspace(0.0, warped[-1], frames)
    compression = (share / slip_time) / ((1 - share) / stick_time)
    return np.interp(targets, warped, time), float(compression)


def _spring(x0, x1, y, coils=8, height=0.18):
    xs = np.linspace(x0, x1, 2 * coils + 3)
    ys = np.full_like(xs, y)
    ys[1:-1:2] += height
    ys[2:-1:2] -= height
    ys[1], ys[-2] = y, y
    return xs, ys


def animation(dataset, frames: int = 120, slip_share: float = 0.5, title: str = ""):
    """A :class:`matplotlib.animation.FuncAnimation` of a simulation (:func:`faultslip.dynamics.spring_slider.simulate.simulate`)
    and the compression factor. Lengths are drawn in units of the cycle's swing."""
    from matplotlib import animation as mpl_animation  # heavy: imported where used

    plt = _pyplot()
    times, compression = frame_times(dataset, frames, slip_share)
    time = dataset["time"].values
    x = dataset["displacement"].values
    velocity = dataset["velocity"].values
    friction = dataset["friction_coefficient"].values
    speed = float(dataset.attrs["platform_speed"])
    fault = dataset.attrs.get("scale") == "fault"
    time_unit, time_scale = ("yr", JULIAN_YEAR) if fault else ("s", 1.0)
    positions = np.interp(times, time, x)
    velocities = np.interp(times, time, velocity)
    frictions = np.interp(times, time, friction)
    swing = max(float(np.ptp(x[time >= time[len(time) // 3]])), 1e-30)
    centre = float(np.mean(x[time >= time[len(time) // 3]]))

    figure, (scene, phase, trace) = plt.subplots(1, 3, figsize=(12, 3.6), constrained_layout=True,
                                                 gridspec_kw={"width_ratios": [1.4, 1, 1.2]})
    scene.set(xlim=(-3.2, 2.2), ylim=(-1.0, 1.2), xticks=[], yticks=[], title="block, spring and platform")
    scene.plot([-3.0, -3.0], [0.05, 0.75], color="k", lw=3)  # the anchor
    spring_line, = scene.plot([], [], color="0.3", lw=1.5)
    block = plt.Rectangle((0, 0.05), 0.7, 0.7, color="C1")
    scene.add_patch(block)
    scene.add_patch(plt.Rectangle((-3.2, -0.35), 5.4, 0.4, color="0.75"))
    ticks = [scene.plot([], [], color="0.45", lw=1)[0] for _ in range(12)]
    status = scene.text(-3.1, -0.85, "", fontsize=8)

    phase.plot(x / swing, velocity / speed, color="0.8", lw=0.8)
    marker, = phase.plot([], [], "o", color="C3")
    phase.set(xlabel="displacement x / swing", ylabel="velocity x' / V", title="phase plane")
    # at fault scale a slip runs at ~1e8 plate rates: a symmetric log axis reads it, where a linear one printed
    # -3e8 under a 1e8 offset; no offset either way
    if np.nanmax(np.abs(velocity / speed)) > 1e3:
        phase.set_yscale("symlog", linthresh=1.0)
    else:
        phase.ticklabel_format(axis="y", useOffset=False)
    phase.ticklabel_format(axis="x", useOffset=False)
    trace.plot(time / time_scale, friction, color="0.7", lw=0.8)
    cursor = trace.axvline(times[0] / time_scale, color="C3")
    now, = trace.plot([], [], "o", color="C3")
    trace.set(xlabel=f"time ({time_unit})", ylabel="friction coefficient", title="friction")
    for axis in (phase, trace):
        axis.grid(True, alpha=0.3)
    figure.suptitle((title or dataset.attrs.get("scene", "")) + (f" - time compressed: a stick plays {compression:.3g}x "
                                                                 "faster than a slip" if compression != 1 else ""),
                    fontsize=9)

    def draw(index):
        left = (positions[index] - centre) / swing  # block position in swings about its mean
        block.set_x(left - 0.35)
        spring_line.set_data(*_spring(-3.0, left - 0.35, 0.4))
        belt = (speed * (times[index] - times[0]) / swing) % 0.45  # the platform's marks move at V
        for k, tick in enumerate(ticks):
            position = -3.2 + belt + 0.45 * k
            tick.set_data([position, position], [-0.35, 0.05] if position < 2.2 else [np.nan, np.nan])
        sliding = abs(velocities[index] - speed) > 1e-6 * speed
        status.set_text(f"{'SLIP' if sliding else 'stick'}   t = {times[index] / time_scale:.4g} {time_unit}")
        block.set_color("C3" if sliding else "C1")
        marker.set_data([positions[index] / swing], [velocities[index] / speed])
        cursor.set_xdata([times[index] / time_scale] * 2)
        now.set_data([times[index] / time_scale], [frictions[index]])
        return [block, spring_line, marker, cursor, now, status, *ticks]

    movie = mpl_animation.FuncAnimation(figure, draw, frames=len(times), blit=False)
    movie.faultslip_frames = (draw, len(times))  # save_gif renders them itself (one draw a frame)
    return movie, figure, compression


def save_gif(movie, figure, path, fps: int = 20, dpi: int = 80, progress=None) -> None:
    """Write the animation as a GIF through pillow, atomically (a temporary file, then renamed).

    ``progress``: True for a bar, or a callable (done, total) over frames (:mod:`faultslip.io.progress`)."""
    from PIL import Image  # heavy: pillow comes with matplotlib; only a GIF needs it

    if not 1 <= fps <= 60:
        raise InputError(f"fps must be from 1 to 60, got {fps}")
    draw, count = movie.faultslip_frames
    movie.pause()  # the frames are rendered below, not by the animation's timer
    progress = reporter(progress, "animation", "frame")
    # Matplotlib's writer saved every frame through savefig: the figure drawn about three times a frame and its
    # constrained layout solved each time (43 % of the run, issue 43). Here the layout is solved once, on the first
    # frame at the GIF's dpi, then frozen; the still parts (axes, ticks, labels, the grey curves) are drawn once
    # into a background, and each frame restores it and draws only the artists that move (blitting).
    figure.set_dpi(dpi)
    canvas = figure.canvas
    moving = draw(0)
    canvas.draw()
    figure.set_layout_engine("none")
    for artist in moving:
        artist.set_animated(True)
    canvas.draw()  # the background: everything but the moving artists
    background = canvas.copy_from_bbox(figure.bbox)
    frames = []
    for index in range(count):
        canvas.restore_region(background)
        for artist in draw(index):
            figure.draw_artist(artist)
        width, height = canvas.get_width_height(physical=True)
        frames.append(Image.frombuffer("RGBA", (width, height), bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
                      .convert("RGB"))  # opaque frames: RGB quantises to GIF's palette better than RGBA
        if progress:
            progress(index + 1, count)
    save_frames(paletted(frames), path, int(1000 / fps))
    _pyplot().close(figure)


def paletted(frames: list) -> list:
    """The frames mapped onto one palette, built once from a montage of four of them.

    Pillow's GIF writer otherwise builds a palette for every frame (median cut, 60-70 % of an animation's time,
    measured); a figure's colours are few and the same in every frame, so one palette serves them all, and
    mapping a frame onto a given palette is a nearest-colour lookup. No dithering: flat colours stay flat."""
    from PIL import Image  # heavy: pillow comes with matplotlib; only a GIF needs it

    picks = frames[:: max(1, len(frames) // 4)][:4]
    width, height = picks[0].size
    montage = Image.new("RGB", (width, height * len(picks)))
    for k, frame in enumerate(picks):
        montage.paste(frame, (0, height * k))
    # the commonest colours exactly (the background, the axes, the artists' fills), the rest by median cut
    # pillow maps onto a palette through a coarse colour cache, where a colour within 8 of another (a near-white
    # beside the white background) can win the bucket: each colour kept is at least 8 from those kept before it
    def distinct(candidates, kept, most):
        for colour in candidates:
            if len(kept) < most and all(max(abs(a - b) for a, b in zip(colour, other)) >= 8 for other in kept):
                kept.append(tuple(colour))
        return kept

    counts = montage.getcolors(maxcolors=montage.width * montage.height)
    kept = distinct((colour for _, colour in sorted(counts, reverse=True)), [], 64)
    cut = montage.quantize(colors=192, method=Image.Quantize.MEDIANCUT).getpalette()[:192 * 3]
    kept = distinct((cut[k:k + 3] for k in range(0, len(cut), 3)), kept, 256)
    entries = [value for colour in kept for value in colour]
    palette = Image.new("P", (1, 1))
    palette.putpalette(entries + [0] * (768 - len(entries)))
    return [frame.quantize(palette=palette, dither=Image.Dither.NONE) for frame in frames]
