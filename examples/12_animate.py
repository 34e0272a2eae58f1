"""Example 12: a still picture with link frames and a GIF of a motion (no ffmpeg, no display).

Run: python examples/12_animate.py   (writes into a temporary folder)
"""

import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

import armkit
from armkit.animation import animate_trajectory, plot_configuration
from armkit.trajectory import min_jerk

robot = armkit.load("zju-i")
folder = Path(tempfile.mkdtemp(prefix="armkit-animation-"))

q = np.full(6, np.pi / 12)  # report 003's configuration
plot_configuration(robot, q, folder / "zju.png", title="ZJU-I, q = 15 deg: DH link frames")

samples = min_jerk([np.zeros(6), q, [0.8, -0.4, 0.9, 0.3, -0.6, 0.5]], [2.0, 2.0]).sample(50.0)
gif = animate_trajectory(robot, samples.q, folder / "zju.gif", t=samples.t, frames=20, title="ZJU-I")
with Image.open(gif) as image:
    print(f"wrote {folder / 'zju.png'} and {gif}: {image.n_frames} frames of {image.size[0]} px, "
          f"{gif.stat().st_size // 1024} kB")
