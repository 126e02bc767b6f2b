#!/usr/bin/env python3
"""Draws plot.png of a trackbed results folder: wall and mesh forces (left) and the energy
budget (right) against time. Usage: plot_history.py RESULTS_DIR"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return [], {}
    header, data = rows[0], rows[1:]
    cols = {h: [float(r[i]) for r in data] for i, h in enumerate(header)}
    return header, cols


def main(folder):
    header, walls = read(os.path.join(folder, "history", "walls.csv"))
    _, energy = read(os.path.join(folder, "history", "energy.csv"))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    t = walls.get("time", [])
    # The vertical loads: reactions of the plane walls (upward positive) and the vertical
    # contact force on every mesh body. Lateral mesh forces where they are not zero.
    for h in header[1:]:
        if "." in h:
            continue
        values = walls[h]
        if h.endswith("_fz"):
            ax1.plot(t, [-v for v in values] if h.replace("_fz", "_x") not in walls else values,
                     label=h[:-3] + (" vertical contact force" if h.replace("_fz", "_x") in walls
                                    else " reaction"))
        elif (h.endswith("_fx") or h.endswith("_fy")) and h.replace(h[-3:], "_x") in walls:
            if any(abs(v) > 1e-9 for v in values):
                ax1.plot(t, values, "--", label=h)
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("force (N)")
    ax1.set_title("Wall and mesh forces")
    ax1.grid(True, alpha=0.3)
    ax1.legend(fontsize=7)
    if energy:
        te = energy["time"]
        for key in ("kinetic", "strain", "friction", "rolling", "dashpot", "local_damping",
                    "gravity_work", "wall_work"):
            if any(abs(v) > 0 for v in energy[key]):
                ax2.plot(te, energy[key], label=key)
        ax2.set_xlabel("time (s)")
        ax2.set_ylabel("energy (J)")
        worst = max(abs(v) for v in energy["balance_error"])
        ax2.set_title("Energy budget (worst balance error %.2g)" % worst)
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(folder, "plot.png")
    fig.savefig(out + ".part.png", dpi=110)
    os.replace(out + ".part.png", out)


if __name__ == "__main__":
    main(sys.argv[1])
