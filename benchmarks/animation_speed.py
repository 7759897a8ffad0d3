"""The animation's cost per frame against matplotlib's own GIF writer, on the same frames (issue 43, item 7).

    python benchmarks/animation_speed.py [--frames 60] [--pairs 3]

The default 1906 scene (two cycles), animated as ``faultslip animate`` does it. Each pair writes the same GIF
twice in this process, interleaved: once through faultslip's ``save_gif`` (the layout solved once, the still
parts drawn once, each frame restoring them and drawing only what moves) and once through matplotlib's
``PillowWriter`` (``FuncAnimation.save``: the figure saved through ``savefig`` each frame, as faultslip's
animation did before issue 43). Both are timed whole (figure building included), wall and CPU, and the
median per frame of each is reported with their ratio. Writes benchmarks/results/animation.json.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import matplotlib  # noqa: E402

matplotlib.use("Agg")

from matplotlib.animation import PillowWriter  # noqa: E402

from faultslip.dynamics.spring_slider.simulate import simulate  # noqa: E402
from faultslip.fault.scene import read_slider_scene  # noqa: E402
from faultslip.plots.animation import animation, save_gif  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)


def _ours(dataset, frames, path):
    movie, figure, _ = animation(dataset, frames=frames)
    save_gif(movie, figure, path, fps=20, dpi=80)


def _matplotlib(dataset, frames, path):
    movie, figure, _ = animation(dataset, frames=frames)
    movie.save(str(path), writer=PillowWriter(fps=20), dpi=80)
    matplotlib.pyplot.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--pairs", type=int, default=3)
    args = parser.parse_args(argv)
    dataset = simulate(read_slider_scene("san_andreas_1906.toml").slider(), cycles=2)
    times = {"faultslip": [], "matplotlib": []}
    with tempfile.TemporaryDirectory() as folder:
        for pair in range(args.pairs):
            for name, write in (("faultslip", _ours), ("matplotlib", _matplotlib)):
                wall, cpu = time.perf_counter(), time.process_time()
                write(dataset, args.frames, Path(folder) / f"{name}{pair}.gif")
                times[name].append(((time.perf_counter() - wall) / args.frames,
                                    (time.process_time() - cpu) / args.frames))
    medians = {name: {"wall_s_per_frame": statistics.median(w for w, _ in rows),
                      "cpu_s_per_frame": statistics.median(c for _, c in rows)} for name, rows in times.items()}
    ratio = medians["matplotlib"]["wall_s_per_frame"] / medians["faultslip"]["wall_s_per_frame"]
    result = {**stamp(), "frames": args.frames, "pairs": args.pairs,
              "medians": medians, "speed_up": ratio,
              "cpu_speed_up": medians["matplotlib"]["cpu_s_per_frame"] / medians["faultslip"]["cpu_s_per_frame"]}
    out = ROOT / "benchmarks" / "results" / "animation.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"faultslip {medians['faultslip']['wall_s_per_frame'] * 1e3:.1f} ms a frame, matplotlib's writer "
          f"{medians['matplotlib']['wall_s_per_frame'] * 1e3:.1f} ms: {ratio:.1f}x (CPU {result['cpu_speed_up']:.1f}x)")


if __name__ == "__main__":
    main()
