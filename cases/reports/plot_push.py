#!/usr/bin/env python3
"""Draws push.png of a push-test results folder: the resistance of the pushed body (lateral in the
lateral push test, vertical in the ballast box) and its shares by mesh part (base, sides, ends)
against its displacement. Usage: plot_push.py RESULTS_DIR"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_push(folder):
    """The columns of FOLDER/push.csv as lists of floats, keyed by header."""
    with open(os.path.join(folder, "push.csv")) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    return {h: [float(r[i]) for r in data] for i, h in enumerate(header)}


def running_mean(d, r, window):
    """r averaged over the rows about each row that stay within +-window/2 of its displacement d,
    contiguous in time (a path passes a displacement more than once), as trackbed's summary does."""
    out = []
    for k, x in enumerate(d):
        first, last = k, k + 1
        while first > 0 and abs(d[first - 1] - x) <= 0.5 * window:
            first -= 1
        while last < len(d) and abs(d[last] - x) <= 0.5 * window:
            last += 1
        out.append(sum(r[first:last]) / (last - first))
    return out


def main(folder):
    push = read_push(folder)
    d = [1e3 * v for v in push["displacement_m"]]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    total = push["resistance_n"]
    ax.plot(d, [1e-3 * v for v in total], "-", color="0.7", lw=0.8, label="total, each row")
    ax.plot(d, [1e-3 * v for v in running_mean(push["displacement_m"], total, 0.0002)], "k-",
            lw=2, label="total, 0.2 mm running mean")
    for h in push:
        if h.startswith("resistance_") and h.endswith("_n") and h != "resistance_n":
            part = h[len("resistance_"):-2]
            ax.plot(d, [1e-3 * v for v in push[h]], "--", label=part)
    ax.set_xlabel("displacement along the push (mm)")
    ax.set_ylabel("resistance against the push (kN)")
    ax.set_title(os.path.basename(os.path.abspath(folder)))
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "push.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
