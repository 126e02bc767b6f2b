#!/usr/bin/env python3
"""Compares the ballast box test of the three shapes with the paper (the paper, Table 1).

Usage: compare.py RESULTS_DIR   (results/ballast_box or results/ballast_box/small)
Reads RESULTS_DIR/<model>/push.csv and summary.json for the models that have run; writes
RESULTS_DIR/comparison.png (the wedge's resistance against its displacement over the path),
comparison.json and comparison.md (contacts and largest contact forces beside Table 1)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reports"))
import study_comparison as sc  # noqa: E402

# model folder, label, the paper's total contacts, max particle-particle and particle-sleeper
# contact force (kN), at the end of the test
PAPER = [
    ("ball", "balls", 5991, 1.3, 13.5),
    ("clump-D120R0.5", "clumps D120/R0.5", 11573, 13.0, 101.6),
    ("clump-D130R0.4", "clumps D130/R0.4", 10536, 21.9, 80.1),
]


def main(results):
    runs = sc.load_runs(results, [p[0] for p in PAPER])
    fig, ax = sc.curves_axes()
    table = []
    for key, label, contacts, fpp, fps in PAPER:
        if key not in runs:
            continue
        sc.plot_curve(ax, runs[key]["push"], label)
        s = runs[key]["summary"]
        table.append(dict(
            model=key, elements=s["elements"], bodies=s["bodies"], contacts=s["contacts"],
            steps=s["steps"], time_step_s=s["time_step_s"], wall_time_s=s["wall_time_s"],
            max_particle_force_end_kn=s["max_particle_contact_force_end_n"] / 1e3,
            max_sleeper_force_end_kn=s["max_sleeper_contact_force_end_n"] / 1e3,
            max_particle_force_test_kn=s["max_particle_contact_force_push_n"] / 1e3,
            max_sleeper_force_test_kn=s["max_sleeper_contact_force_push_n"] / 1e3,
            peak_lift_kn=s["peak_vertical_force_n"] / 1e3,
            peak_compaction_kn=s["peak_reverse_vertical_force_n"] / 1e3,
            paper_contacts=contacts, paper_max_particle_force_kn=fpp,
            paper_max_sleeper_force_kn=fps))
    sc.save_curves(fig, ax, results,
                   "vertical displacement of the wedge (mm): up, down to compact, back",
                   "resistance against its motion",
                   "Ballast box test, three shapes (positive: against lifting)")
    sc.write_table(
        results, table,
        ["shape", "elements", "contacts at the end (paper)",
         "max particle-particle kN: end, test (paper)",
         "max particle-sleeper kN: end, test (paper)", "peak lift / compaction kN",
         "wall time s"],
        lambda r: [r["model"], "%d" % r["elements"],
                   "%d (%d)" % (r["contacts"], r["paper_contacts"]),
                   "%.3f, %.3f (%.1f)" % (r["max_particle_force_end_kn"],
                                          r["max_particle_force_test_kn"],
                                          r["paper_max_particle_force_kn"]),
                   "%.3f, %.3f (%.1f)" % (r["max_sleeper_force_end_kn"],
                                          r["max_sleeper_force_test_kn"],
                                          r["paper_max_sleeper_force_kn"]),
                   "%.3f / %.3f" % (r["peak_lift_kn"], r["peak_compaction_kn"]),
                   "%.0f" % r["wall_time_s"]])


if __name__ == "__main__":
    main(sys.argv[1])
