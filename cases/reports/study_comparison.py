"""What the compare.py of every study (cases/<study>/compare.py) shares: the runs of its models
found under a results folder, the figure of their resistance curves against the displacement
(comparison.png), and the table beside the paper's figures (comparison.json and comparison.md)."""
import json
import os
import sys

import matplotlib

from plot_push import read_push, running_mean

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load_runs(results, models):
    """{model: {"summary": summary.json, "push": push.csv columns}} for the models of the list
    that have run under RESULTS (a folder each), in the list's order; exits if none has."""
    runs = {}
    for model in models:
        folder = os.path.join(results, model)
        if not os.path.exists(os.path.join(folder, "summary.json")):
            continue
        with open(os.path.join(folder, "summary.json")) as f:
            runs[model] = dict(summary=json.load(f), push=read_push(folder))
    if not runs:
        sys.exit("compare.py: no model results under " + results)
    return runs


def curves_axes():
    """The figure and axes of comparison.png."""
    return plt.subplots(figsize=(8, 5))


def plot_curve(ax, push, label, color=None):
    """A run's resistance (kN) against its displacement (mm), 0.2 mm running mean."""
    d, r = push["displacement_m"], push["resistance_n"]
    ax.plot([1e3 * x for x in d], [1e-3 * v for v in running_mean(d, r, 0.0002)], color=color,
            label=label)


def save_curves(fig, ax, results, xlabel, ylabel, title):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel + " (kN), 0.2 mm running mean")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "comparison.png"), dpi=130)


def write_table(results, table, header, row):
    """comparison.json (TABLE, a list of dicts) and comparison.md: the markdown HEADER (a list of
    column titles) and one line per entry, ROW(entry) giving its cells as strings; printed."""
    with open(os.path.join(results, "comparison.json"), "w") as f:
        json.dump(table, f, indent=2)
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row(entry)) + " |" for entry in table]
    with open(os.path.join(results, "comparison.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
