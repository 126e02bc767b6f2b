#!/usr/bin/env python3
"""Compares the ballast box test of the three shapes with the paper (seed-facts.md, Table 1).

Usage: compare.py RESULTS_DIR   (results/ballast_box or results/ballast_box/small)
Reads RESULTS_DIR/<model>/push.csv and summary.json for the models that have run; writes
RESULTS_DIR/comparison.png (the wedge's resistance against its displacement over the path),
comparison.json and comparison.md (contacts and largest contact forces beside Table 1)."""
import json
import os
import sys

import matplotlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from plot_push import read_push, running_mean  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# model folder, label, the paper's total contacts, max particle-particle and particle-sleeper
# contact force (kN), at the end of the test
PAPER = [
    ("ball", "balls", 5991, 1.3, 13.5),
    ("clump-D120R0.5", "clumps D120/R0.5", 11573, 13.0, 101.6),
    ("clump-D130R0.4", "clumps D130/R0.4", 10536, 21.9, 80.1),
]


def main(results):
    models = []
    for key, label, contacts, fpp, fps in PAPER:
        folder = os.path.join(results, key)
        if not os.path.exists(os.path.join(folder, "summary.json")):
            continue
        with open(os.path.join(folder, "summary.json")) as f:
            s = json.load(f)
        models.append(dict(key=key, label=label, paper=(contacts, fpp, fps), summary=s,
                           push=read_push(folder)))
    if not models:
        sys.exit("compare.py: no model results under " + results)

    fig, ax = plt.subplots(figsize=(8, 5))
    for m in models:
        d, r = m["push"]["displacement_m"], m["push"]["resistance_n"]
        ax.plot([1e3 * x for x in d], [1e-3 * v for v in running_mean(d, r, 0.0002)],
                label=m["label"])
    ax.set_xlabel("vertical displacement of the wedge (mm): up, down to compact, back")
    ax.set_ylabel("resistance against its motion (kN), 0.2 mm running mean")
    ax.set_title("Ballast box test, three shapes (positive: against lifting)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "comparison.png"), dpi=130)

    table = []
    for m in models:
        s = m["summary"]
        table.append(dict(
            model=m["key"], elements=s["elements"], bodies=s["bodies"], contacts=s["contacts"],
            steps=s["steps"], time_step_s=s["time_step_s"], wall_time_s=s["wall_time_s"],
            max_particle_force_end_kn=s["max_particle_contact_force_end_n"] / 1e3,
            max_sleeper_force_end_kn=s["max_sleeper_contact_force_end_n"] / 1e3,
            max_particle_force_test_kn=s["max_particle_contact_force_push_n"] / 1e3,
            max_sleeper_force_test_kn=s["max_sleeper_contact_force_push_n"] / 1e3,
            peak_lift_kn=s["peak_vertical_force_n"] / 1e3,
            peak_compaction_kn=s["peak_reverse_vertical_force_n"] / 1e3,
            paper_contacts=m["paper"][0], paper_max_particle_force_kn=m["paper"][1],
            paper_max_sleeper_force_kn=m["paper"][2]))
    with open(os.path.join(results, "comparison.json"), "w") as f:
        json.dump(table, f, indent=2)

    lines = ["| shape | elements | contacts at the end (paper) | max particle-particle kN: end, "
             "test (paper) | max particle-sleeper kN: end, test (paper) | peak lift / compaction "
             "kN | wall time s |", "|" + "---|" * 7]
    for row in table:
        lines.append("| %s | %d | %d (%d) | %.3f, %.3f (%.1f) | %.3f, %.3f (%.1f) | %.3f / %.3f "
                     "| %.0f |" % (
                         row["model"], row["elements"], row["contacts"], row["paper_contacts"],
                         row["max_particle_force_end_kn"], row["max_particle_force_test_kn"],
                         row["paper_max_particle_force_kn"], row["max_sleeper_force_end_kn"],
                         row["max_sleeper_force_test_kn"], row["paper_max_sleeper_force_kn"],
                         row["peak_lift_kn"], row["peak_compaction_kn"], row["wall_time_s"]))
    with open(os.path.join(results, "comparison.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1])
