#!/usr/bin/env python3
"""Draws the pictures of a trackbed sample folder (trackbed build-sample):
  grading.png  the grading curve: target sieve table and the sample's (and the base sample's);
  sample.png   a cross-section of the bed at y = 0 (mid-sleeper) and a view from above, drawn
               from particles.vtu and walls.vtu: balls grey, clumps in colours by body.
Usage: plot_sample.py SAMPLE_DIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trackbed_vtu import read_vtu  # noqa: E402


def save(fig, path):
    # Written under a temporary name and renamed, as every trackbed output.
    tmp = path + ".part.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def plot_grading(folder):
    with open(os.path.join(folder, "grading.csv")) as f:
        lines = [line for line in f if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    size = [1000 * float(r["size"]) for r in rows]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(size, [float(r["target"]) for r in rows], "k-o", label="target (sieve table)")
    ax.plot(size, [float(r["sample"]) for r in rows], "r--s", label="sample (sieve size)")
    if any(r["sample"] != r.get("sample_equivalent_diameter", r["sample"]) for r in rows):
        ax.plot(size, [float(r["sample_equivalent_diameter"]) for r in rows], "g-.d",
                label="sample (equivalent diameter)")
    if "base" in rows[0]:
        ax.plot(size, [float(r["base"]) for r in rows], "b:^", label="ball sample before conversion")
    ax.set_xscale("log")
    ax.set_xticks(size)
    ax.set_xticklabels([f"{s:g}" for s in size])
    ax.set_xlabel("sieve size (mm)")
    ax.set_ylabel("passing by mass (%)")
    ax.set_ylim(-2, 102)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    ax.set_title("Grading")
    fig.tight_layout()
    save(fig, os.path.join(folder, "grading.png"))


def colours(body, clump):
    palette = plt.get_cmap("tab20")(np.arange(20))
    c = palette[body.astype(np.int64) % 20].copy()
    c[clump == 0] = (0.62, 0.62, 0.62, 1.0)
    return c


def plot_sample(folder):
    vtu = read_vtu(os.path.join(folder, "particles.vtu"))
    x = vtu["points"]
    r = vtu["point_data"]["radius"]
    body = vtu["point_data"]["body"]
    clump = vtu["point_data"]["clump"]
    walls = read_vtu(os.path.join(folder, "walls.vtu"))
    sleeper = None
    if len(walls["cell_data"]["wall"]):
        last = walls["cell_data"]["wall"].max()
        pts = walls["points"].reshape(-1, 3, 3)[walls["cell_data"]["wall"] == last].reshape(-1, 3)
        if len(pts) == 36:  # a box: 12 triangles
            sleeper = (pts.min(axis=0), pts.max(axis=0))
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)

    # Panels in true proportions: a section is some ten times wider than high.
    span = np.ptp(x, axis=0) + 0.1
    width = 12.0
    h1, h2 = width * span[2] / span[0], width * span[1] / span[0]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(width, h1 + h2 + 2.2),
                                   gridspec_kw={"height_ratios": [h1, h2]})
    # Cross-section: the circle each sphere cuts from the plane y = 0.
    cut = np.abs(x[:, 1]) < r
    rc = np.sqrt(r[cut] ** 2 - x[cut, 1] ** 2)
    ax1.add_collection(EllipseCollection(2 * rc, 2 * rc, 0, units="xy", offsets=x[cut][:, [0, 2]],
                                         transOffset=ax1.transData, facecolors=colours(
                                             body[cut], clump[cut]), edgecolors="k",
                                         linewidths=0.2))
    # View from above: spheres drawn from the lowest up, so the top layer shows.
    order = np.argsort(x[:, 2])
    ax2.add_collection(EllipseCollection(2 * r[order], 2 * r[order], 0, units="xy",
                                         offsets=x[order][:, [0, 1]], transOffset=ax2.transData,
                                         facecolors=colours(body[order], clump[order]),
                                         edgecolors="k", linewidths=0.1))
    for ax, (a, b) in ((ax1, (0, 2)), (ax2, (0, 1))):
        if sleeper is not None:
            lo, hi = sleeper
            ax.add_patch(Rectangle((lo[a], lo[b]), hi[a] - lo[a], hi[b] - lo[b], fill=False,
                                   edgecolor="b", linewidth=1.5, zorder=5))
        ax.set_xlim(x[:, a].min() - 0.05, x[:, a].max() + 0.05)
        ax.set_ylim(x[:, b].min() - 0.05, x[:, b].max() + 0.05)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m), across the track")
        ax.set_ylabel("z (m)" if b == 2 else "y (m), along the track")
    ax1.set_title(f"Cross-section at y = 0: {summary['balls']:.0f} balls (grey), "
                  f"{summary['clumps']:.0f} clumps (colours), {summary['elements']:.0f} sphere "
                  f"elements\nporosity under the sleeper {summary['porosity_under_sleeper']:.3f}",
                  fontsize=10)
    ax2.set_title("From above (sleeper outlined in blue)", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(folder, "sample.png"))


if __name__ == "__main__":
    folder = sys.argv[1]
    plot_grading(folder)
    if os.path.exists(os.path.join(folder, "particles.vtu")):
        plot_sample(folder)
