#!/usr/bin/env python3
"""Draws displacement.png of a push test's results folder (dem_run.cc draws it after every push):
how far every sphere element has moved since the run's start, at its last particles VTU frame
(vtu/particles-NNNNNN.vtu), as the laboratory's displacement map of a push test shows it
(the paper: the "most influential zone"). Two views:
from above (every element, the highest drawn last, so the bed's surface shows) and a section
along the sleeper's length through its middle (the elements within 50 mm of y = 0), coloured by
the displacement's magnitude in mm, the scale ending at the push's largest displacement or,
without a push, at the 99th percentile.
Usage: plot_displacement.py RESULTS_DIR   (no particles VTU with displacements: nothing drawn)"""
import glob
import os
import sys

import matplotlib
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trackbed_vtu import read_vtu  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SECTION_HALF_WIDTH = 0.05  # m: the section's slice, about one stone


def sleeper_displacement(folder):
    """The push's largest displacement (push.csv), m; None without a push test."""
    path = os.path.join(folder, "push.csv")
    if not os.path.exists(path):
        return None
    rows = np.genfromtxt(path, delimiter=",", names=True)
    return float(np.max(np.abs(np.atleast_1d(rows["displacement_m"]))))


def main(folder):
    frames = sorted(glob.glob(os.path.join(folder, "vtu", "particles-*.vtu")))
    if not frames:
        print("plot_displacement.py: no particles VTU in " + folder)
        return
    vtu = read_vtu(frames[-1])
    if "displacement" not in vtu["point_data"] or len(vtu["points"]) == 0:
        print("plot_displacement.py: no displacements in " + frames[-1])
        return
    x = vtu["points"]
    d = 1e3 * np.linalg.norm(vtu["point_data"]["displacement"], axis=1)  # mm
    r = vtu["point_data"]["radius"]
    push = sleeper_displacement(folder)
    top = 1e3 * push if push else float(np.percentile(d, 99))
    section = np.flatnonzero(np.abs(x[:, 1]) <= SECTION_HALF_WIDTH)
    section = section[np.argsort(-x[section, 1] ** 2)]  # those nearest the middle on top
    fig, axes = plt.subplots(2, 1, figsize=(12, 7.5))
    views = [
        (axes[0], np.argsort(x[:, 2]), 1, "y (m)", "from above (the highest elements on top)"),
        (axes[1], section, 2, "z (m)",
         "section along the sleeper, |y| <= %.0f mm" % (1e3 * SECTION_HALF_WIDTH)),
    ]
    for ax, pick, b, label, title in views:
        # Marker areas in points^2 from radii in m: the figure's scale, about 170 points per m.
        dots = ax.scatter(x[pick, 0], x[pick, b], c=np.minimum(d[pick], top), s=(170 * r[pick]) ** 2,
                          cmap="viridis", vmin=0, vmax=top, linewidths=0)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m), the push along +x")
        ax.set_ylabel(label)
        ax.set_title("Displacement since the run's start (hold and push), " + title, fontsize=9)
        fig.colorbar(dots, ax=ax, label="mm" + (" (capped at the push)" if push else ""),
                     shrink=0.8)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "displacement.png"), dpi=130)


if __name__ == "__main__":
    main(sys.argv[1])
