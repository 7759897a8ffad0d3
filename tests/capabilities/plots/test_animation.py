"""faultslip animate: a GIF of the slider beside the phase plane and friction, at lab and fault scale."""

import numpy as np
import pytest
from PIL import Image

from conftest import assert_clean_error
from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.errors import InputError
from faultslip.fault.scene import read_slider_scene
from faultslip.plots.animation import frame_times


def test_frames_give_slip_phases_their_share_and_state_the_compression():
    """1906: slips of 21.6 s between sticks of ~127 yr. Half the frames fall in slips, so a stick plays
    (share / slip time) / ((1 - share) / stick time) = stick / slip = 1.85e8 times faster per cycle."""
    dataset = simulate(read_slider_scene("san_andreas_1906.toml").slider(), cycles=3)
    times, compression = frame_times(dataset, 200)
    slipping = np.interp(times, dataset["time"].values, (dataset["phase"].values == 1).astype(float)) > 0.5
    assert 0.4 < slipping.mean() < 0.6
    steps = np.diff(dataset["time"].values)
    sliding = dataset["phase"].values[1:] == 1
    assert compression == pytest.approx(steps[~sliding].sum() / steps[sliding].sum(), rel=1e-9)
    assert np.all(np.diff(times) >= 0)
    with pytest.raises(InputError, match="frames"):
        frame_times(dataset, 1)


@pytest.mark.parametrize("scene", ["configs/lab_glass_dry.toml", "san_andreas_1906.toml"])
def test_the_gif_has_the_frames_asked_for(cli, tmp_path, scene):
    out = cli("animate", scene, "-o", tmp_path / "a.gif", "--frames", "12", "--fps", "10", "--json")
    assert out.code == 0, out.err
    with Image.open(tmp_path / "a.gif") as gif:
        assert gif.n_frames == 12 and gif.size == (960, 288)
    assert out.json["compression"] > 100  # the time axis is compressed, and the report says how much


def test_animate_refuses_bad_requests(cli, tmp_path):
    assert_clean_error(cli("animate", "configs/lab_glass_dry.toml", "-o", tmp_path / "a.png"), "-o")
    assert_clean_error(cli("animate", "configs/lab_glass_dry.toml", "-o", tmp_path / "a.gif", "--frames", "1"),
                       "--frames must be from 2")
    assert_clean_error(cli("animate", "configs/lab_glass_dry.toml", "-o", tmp_path / "a.gif", "--fps", "500"), "fps")


def test_the_frozen_layout_draws_what_matplotlibs_writer_draws(tmp_path):
    """save_gif solves the layout once, draws the still parts once and blits only the moving artists each frame
    (matplotlib's PillowWriter saved every frame through savefig: about three draws and a constrained-layout solve
    a frame, 43 % of the time), and maps every frame onto one palette (pillow's writer built one a frame, most of
    what remained). Its frames are matplotlib's own to the GIF's quantisation (benchmarks/animation_speed.py:
    33.7x faster a frame)."""
    from matplotlib.animation import PillowWriter

    from faultslip.plots.animation import animation, save_gif

    dataset = simulate(read_slider_scene("san_andreas_1906.toml").slider(), cycles=2)
    movie, figure, _ = animation(dataset, frames=6)
    save_gif(movie, figure, tmp_path / "ours.gif", fps=10, dpi=80)
    movie, figure, _ = animation(dataset, frames=6)
    movie.save(str(tmp_path / "theirs.gif"), writer=PillowWriter(fps=10), dpi=80)
    with Image.open(tmp_path / "ours.gif") as ours, Image.open(tmp_path / "theirs.gif") as theirs:
        assert ours.n_frames == theirs.n_frames == 6 and ours.size == theirs.size
        for frame in (0, 3, 5):
            ours.seek(frame)
            theirs.seek(frame)
            a = np.asarray(ours.convert("RGB"), dtype=float)
            b = np.asarray(theirs.convert("RGB"), dtype=float)
            # both GIFs are quantised, each its own way (matplotlib's writer builds a palette a frame, save_gif one
            # for all: faultslip.plots.animation.paletted), and differ by about 0.2 on average; two neighbouring
            # frames differ by 2-4, so this still tells any moved artist
            assert np.mean(np.abs(a - b)) < 0.5
