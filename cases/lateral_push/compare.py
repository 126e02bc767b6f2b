#!/usr/bin/env python3
"""Compares the five lateral push models of one size with the paper (seed-facts.md, Table 3).

Usage: compare.py RESULTS_DIR   (results/lateral_push or results/lateral_push/small)
Reads RESULTS_DIR/<model>/push.csv and summary.json for the models that have run; writes
RESULTS_DIR/comparison.png (the force-displacement curves, the paper's peaks marked),
comparison.json and comparison.md (a table beside the paper's figures)."""
import json
import os
import sys

import matplotlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from plot_push import read_push, running_mean  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# model folder, label, the paper's elements, wall time (s), peak (kN), max contact force (kN)
PAPER = [
    ("all-clump", "all clumps (reference)", 647323, 43 * 3600 + 23 * 60, 12.03, 2.18),
    ("half-by-height", "multi-layer, half by height", 264109, 15 * 3600 + 45 * 60, 9.92, 1.56),
    ("optimised", "multi-layer, optimised zone", 150746, 10 * 3600 + 25 * 60, 11.20, 2.93),
    ("all-ball-rolling", "all balls, mu_r 0.3", 24394, 2 * 3600 + 32 * 60, 16.02, 4.65),
    ("all-ball", "all balls, no rolling resistance", 24394, 3 * 3600 + 5 * 60, 3.76, 0.37),
]


def hms(s):
    s = int(round(s))
    return "%d h %02d min" % (s // 3600, (s // 60) % 60) if s >= 3600 else "%d min %02d s" % (
        s // 60, s % 60)


def main(results):
    models = []
    for key, label, elements, wall, peak, fmax in PAPER:
        folder = os.path.join(results, key)
        if not os.path.exists(os.path.join(folder, "summary.json")):
            continue
        with open(os.path.join(folder, "summary.json")) as f:
            s = json.load(f)
        push = read_push(folder)
        d, r = push["displacement_m"], push["resistance_n"]
        models.append(dict(key=key, label=label, paper_elements=elements, paper_wall_s=wall,
                           paper_peak_kn=peak, paper_max_force_kn=fmax, summary=s, d=d, r=r))
    if not models:
        sys.exit("compare.py: no model results under " + results)

    ref = next((m for m in models if m["key"] == "all-clump"), None)
    # The paper's peaks, or, with our reference run, the paper's peak ratios to its reference
    # applied to ours: comparable at any scale (the scaled-down section resists far less).
    scale = 1.0 if ref is None else ref["summary"]["peak_lateral_force_n"] / 1e3 / PAPER[0][4]
    fig, ax = plt.subplots(figsize=(8, 5))
    for i, m in enumerate(models):
        color = "C%d" % i
        ax.plot([1e3 * x for x in m["d"]], [1e-3 * v for v in running_mean(m["d"], m["r"], 0.0002)],
                color=color, label=m["label"])
        ax.plot([5.15], [scale * m["paper_peak_kn"]], marker="<", color=color, ms=9, clip_on=False)
    ax.set_xlim(0, 5.3)
    ax.set_xlabel("lateral displacement of the sleeper (mm)")
    ax.set_ylabel("lateral resistance (kN), 0.2 mm running mean")
    ax.set_title("Lateral push, five models; triangles: the paper's peaks (Table 3)" +
                 ("" if ref is None else ",\nas ratios to its all-clump peak applied to ours"),
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "comparison.png"), dpi=130)

    table = []
    for m in models:
        s = m["summary"]
        row = dict(model=m["key"], elements=s["elements"], bodies=s["bodies"],
                   clumps=s["clumps"], contacts=s["contacts"], steps=s["steps"],
                   time_step_s=s["time_step_s"], wall_time_s=s["wall_time_s"],
                   peak_kn=s["peak_lateral_force_n"] / 1e3,
                   force_at_2mm_kn=s.get("lateral_force_at_2mm_n", float("nan")) / 1e3,
                   max_particle_force_kn=s["max_particle_contact_force_end_n"] / 1e3,
                   max_sleeper_force_kn=s["max_sleeper_contact_force_end_n"] / 1e3,
                   share_base=s.get("share_base"), share_sides=s.get("share_sides"),
                   share_ends=s.get("share_ends"),
                   paper_elements=m["paper_elements"], paper_wall_time_s=m["paper_wall_s"],
                   paper_peak_kn=m["paper_peak_kn"], paper_max_force_kn=m["paper_max_force_kn"])
        if ref:
            row["peak_over_reference"] = s["peak_lateral_force_n"] / ref["summary"][
                "peak_lateral_force_n"]
            row["cost_over_reference"] = s["wall_time_s"] / ref["summary"]["wall_time_s"]
        table.append(row)
    with open(os.path.join(results, "comparison.json"), "w") as f:
        json.dump(table, f, indent=2)

    lines = ["| model | elements (paper) | wall time (paper) | peak kN (paper) | at 2 mm kN | "
             "max particle kN (paper) | max sleeper kN | base / sides / ends | peak / ref | "
             "cost / ref |", "|" + "---|" * 10]
    for row in table:
        ratio = lambda k: "%.2f" % row[k] if k in row else "-"  # noqa: E731
        lines.append(
            "| %s | %d (%d) | %s (%s) | %.2f (%.2f) | %.2f | %.2f (%.2f) | %.2f | %.0f / %.0f / %.0f %% "
            "| %s | %s |" % (row["model"], row["elements"], row["paper_elements"],
                             hms(row["wall_time_s"]), hms(row["paper_wall_time_s"]),
                             row["peak_kn"], row["paper_peak_kn"], row["force_at_2mm_kn"],
                             row["max_particle_force_kn"], row["paper_max_force_kn"],
                             row["max_sleeper_force_kn"], 100 * row["share_base"],
                             100 * row["share_sides"], 100 * row["share_ends"],
                             ratio("peak_over_reference"), ratio("cost_over_reference")))
    with open(os.path.join(results, "comparison.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1])
