#!/usr/bin/env python3
"""Draws docs/images/lateral-push-ball-seating.png: the full-size ball push with rolling
resistance (all-ball-rolling.prm as shipped) on ball samples whose sleeper was seated on the
finished profile (the default) and in the mould (docs/samples.md, "Seating in the mould"), with
the reference (all-clump) for scale; 0.2 mm running means of push.csv.
Usage: docs/data/lateral-push-full/plot_seating.py (from the repository root)"""
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "cases", "reports"))
import plot_push as pp  # noqa: E402

RUNS = [  # folder, label, style
    ("all-ball-rolling-sleeper-rolling", "balls, seated on the profile (ninth build)", "b--"),
    ("all-ball-rolling-third-sleeper-rolling", "balls, seated on the profile (third build)", "c--"),
    ("all-ball-rolling-mould", "balls, seated in the mould (seed 1)", "b-"),
    ("all-ball-rolling-mould-s2", "balls, seated in the mould (seed 2)", "c-"),
    ("all-clump", "all clumps (reference)", "k-"),
]

fig, ax = pp.plt.subplots(figsize=(7, 4.5))
for folder, label, style in RUNS:
    path = os.path.join(here, folder)
    if not os.path.exists(os.path.join(path, "push.csv")):
        continue
    push = pp.read_push(path)
    mean = pp.running_mean(push["displacement_m"], push["resistance_n"], 0.0002)
    ax.plot([1e3 * v for v in push["displacement_m"]], [1e-3 * v for v in mean], style, lw=1.5,
            label=label)
ax.set_xlabel("sleeper displacement (mm)")
ax.set_ylabel("lateral resistance (kN)")
ax.set_title("Full-size lateral push: where the ball sample's sleeper was seated")
ax.grid(True, alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(here, "..", "..", "images", "lateral-push-ball-seating.png"), dpi=120)
