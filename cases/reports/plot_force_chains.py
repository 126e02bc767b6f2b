#!/usr/bin/env python3
"""Draws force_chains.png of a results folder: the contact forces of its last contacts VTU frame
(vtu/contacts-NNNNNN.vtu of a run, or contacts.vtu of a sample) as lines between the contacting
centres, seen from the front (x-z) and from the side (y-z), each line as wide and as dark as its
force is large; contacts with walls and meshes (the sleeper) in red.
Usage: plot_force_chains.py RESULTS_DIR   (no contacts VTU: nothing is drawn)"""
import glob
import os
import sys

import matplotlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trackbed_vtu import read_vtu  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402


def last_frame(folder):
    frames = sorted(glob.glob(os.path.join(folder, "vtu", "contacts-*.vtu")))
    if frames:
        return frames[-1]
    single = os.path.join(folder, "contacts.vtu")
    return single if os.path.exists(single) else None


def main(folder):
    path = last_frame(folder)
    if path is None:
        print("plot_force_chains.py: no contacts VTU in " + folder)
        return
    vtu = read_vtu(path)
    p, force = vtu["points"], vtu["cell_data"]["force_magnitude"]
    wall = vtu["cell_data"]["wall_contact"]
    if len(force) == 0:
        print("plot_force_chains.py: no contacts in " + path)
        return
    top = float(force.max())
    order = force.argsort()  # the strongest drawn last, on top
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), gridspec_kw={"width_ratios": [1.6, 1]})
    for ax, (a, b, name) in zip(axes, [(0, 2, "x"), (1, 2, "y")]):
        segments = [[(p[2 * c, a], p[2 * c, b]), (p[2 * c + 1, a], p[2 * c + 1, b])] for c in order]
        share = force[order] / top
        colours = [(0.8, 0.1, 0.1, 0.2 + 0.8 * s) if wall[c] else (0, 0, 0, 0.15 + 0.85 * s)
                   for c, s in zip(order, share)]
        ax.add_collection(LineCollection(segments, linewidths=0.2 + 3.8 * share, colors=colours))
        ax.autoscale()
        ax.set_aspect("equal")
        ax.set_xlabel(name + " (m)")
        ax.set_ylabel("z (m)")
    axes[0].set_title("Force chains seen along y (width and darkness: force; red: walls and "
                      "meshes)", fontsize=9)
    axes[1].set_title("seen along x; largest force %.3g kN, %d contacts" % (top / 1e3, len(force)),
                      fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "force_chains.png"), dpi=130)


if __name__ == "__main__":
    main(sys.argv[1])
