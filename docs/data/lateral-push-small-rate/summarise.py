#!/usr/bin/env python3
"""The scaled-down all-clump push at several velocities and contact variants (README.md here):
prints the table of docs/validation.md ("What makes the clump bed's resistance depend on the
velocity") and draws docs/images/lateral-push-small-rate.png.

Per run, from push.csv: the peak of the 0.2 mm running mean of the resistance R; the mean of R
over 1-5 mm; the mean over 1-5 mm of what reaches the walls, R + wall_load_sum_n (the base's
friction: the crib walls are frictionless); the balance error |mean wall_load_sum_n| / mean R
over the push (the part of R that local damping and inertia take); from sleeper.csv the
sleeper's sink since the push started, at 2 and 5 mm of push.
Usage: docs/data/lateral-push-small-rate/summarise.py (from the repository root)"""
import csv
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "cases", "reports"))
import plot_push as pp  # noqa: E402

RUNS = [  # folder, what differs from the shipped scaled-down all-clump push
    ("v10", "none (the shipped push)"),
    ("v5", "none"),
    ("v2.5", "none"),
    ("v10-dt0.3", "time step 0.3 of the critical one (shipped: 0.8)"),
    ("v10-dt0.7", "time step 0.7 of the critical one"),
    ("v10-dt0.9", "time step 0.9 of the critical one"),
    ("hold2-v10", "held 2 s before the push (shipped: until at rest, 0.023 s)"),
    ("D130-v10", "clumps D130/R0.4 (21.5 pebbles; shipped D120/R0.5, 8.3)"),
    ("D130-v5", "clumps D130/R0.4"),
    ("roll-v10", "rolling friction 0.3 at every clump contact"),
    ("roll-v5", "rolling friction 0.3 at every clump contact"),
    ("roll0.03-v10", "rolling friction 0.03 at every clump contact"),
    ("roll0.1-v10", "rolling friction 0.1 at every clump contact"),
    ("rollbed-v10", "rolling friction 0.3 between stones and on the base, none at the sleeper"),
    ("rollbed-v5", "rolling friction 0.3 between stones and on the base, none at the sleeper"),
    ("rollsleeper-v10", "rolling friction 0.3 at the sleeper only"),
    ("ndamp-v10", "normal damping ratio 0.1 at clump contacts (shipped: 0)"),
    ("ndamp-v5", "normal damping ratio 0.1 at clump contacts"),
    ("ld0.3-v10", "local damping 0.3 on the clumps (shipped: 0.7)"),
    ("ld0.3-v5", "local damping 0.3 on the clumps"),
    ("dense-v10", "clumps grown at friction x 0.3 (porosity under the sleeper 0.431, shipped 0.438)"),
    ("dense-v5", "clumps grown at friction x 0.3"),
]

MODELS = [  # the five models of the scaled-down section; folder prefix ("": the all-clump runs)
    ("all-clump", ""),
    ("half by height", "hbh"),
    ("optimised", "opt"),
    ("all-ball-rolling", "ballroll"),
    ("all-ball", "ball"),
]


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def figures(folder):
    push = read_csv(os.path.join(folder, "push.csv"))
    x, r, w = push["displacement_m"], push["resistance_n"], push["wall_load_sum_n"]
    mean = pp.running_mean(x, r, 0.0002)
    over = [i for i, d in enumerate(x) if 0.001 <= d <= 0.005]
    sleeper = read_csv(os.path.join(folder, "sleeper.csv"))
    start = push["time_s"][0]
    z0 = sleeper["z_m"][min(range(len(sleeper["time_s"])),
                            key=lambda i: abs(sleeper["time_s"][i] - start))]

    def sink_at(d):
        t = push["time_s"][min(range(len(x)), key=lambda i: abs(x[i] - d))]
        k = min(range(len(sleeper["time_s"])), key=lambda i: abs(sleeper["time_s"][i] - t))
        return 1e3 * (z0 - sleeper["z_m"][k])

    return {
        "velocity": 1e3 * (x[-1] - x[0]) / (push["time_s"][-1] - start),
        "peak": max(m for m, d in zip(mean, x) if d >= 0.0002),
        "mean": sum(r[i] for i in over) / len(over),
        "walls": sum(r[i] + w[i] for i in over) / len(over),
        "balance": abs(sum(w) / len(w)) / (sum(r) / len(r)),
        "sink2": sink_at(0.002),
        "sink5": sink_at(x[-1]),
        "curve": ([1e3 * d for d in x], mean),
        "walls_curve": pp.running_mean(x, [a + b for a, b in zip(r, w)], 0.0002),
    }


def main():
    print("| run | differs from the shipped push | velocity | peak | mean R, 1-5 mm | reaching "
          "the walls, 1-5 mm | balance error | sleeper sink at 2 / 5 mm |")
    print("|---|---|---|---|---|---|---|---|")
    results = {}
    for name, what in RUNS:
        f = figures(os.path.join(here, name))
        results[name] = f
        print(f"| `{name}` | {what} | {f['velocity']:.1f} mm/s | {f['peak']:.1f} N | "
              f"{f['mean']:.1f} N | {f['walls']:.1f} N | {f['balance']:.2f} | "
              f"{f['sink2']:.2f} / {f['sink5']:.2f} mm |")

    print()
    print("| model | clumps' rolling friction | velocity | peak (/ all-clump) | mean R, 1-5 mm "
          "(/ all-clump) | reaching the walls, 1-5 mm (/ all-clump) | balance error |")
    print("|---|---|---|---|---|---|---|")
    for velocity in ("v10", "v5"):
        for rolling in ("", "roll-"):
            reference = figures(os.path.join(here, rolling + velocity))
            for model, folder in MODELS:
                name = f"{folder}-{rolling}{velocity}" if folder else rolling + velocity
                if not os.path.exists(os.path.join(here, name)):
                    name = f"{folder}-{velocity}"  # the ball beds have no clumps
                if not os.path.exists(os.path.join(here, name)):
                    continue
                f = figures(os.path.join(here, name))
                print(f"| {model} | {'0.3' if rolling else '0 (Table 2)'} | {f['velocity']:.0f} mm/s | "
                      + " | ".join(f"{f[k]:.1f} N ({f[k] / reference[k]:.2f})"
                                   for k in ("peak", "mean", "walls"))
                      + f" | {f['balance']:.2f} |")

    fig, axes = pp.plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for name, label, style in [("v10", "10 mm/s", "k-"), ("v5", "5 mm/s", "k--"),
                               ("v2.5", "2.5 mm/s", "k:"),
                               ("rollbed-v10", "stones with rolling friction, 10 mm/s", "b-"),
                               ("rollbed-v5", "stones with rolling friction, 5 mm/s", "b--")]:
        xs, mean = results[name]["curve"]
        axes[0].plot(xs, mean, style, lw=1.5, label=label)
        axes[1].plot(xs, results[name]["walls_curve"], style, lw=1.5, label=label)
    axes[0].set_title("on the sleeper: R")
    axes[1].set_title("reaching the walls: R + wall_load_sum_n")
    axes[0].set_ylabel("lateral force, 0.2 mm mean (N)")
    for ax in axes:
        ax.set_xlabel("sleeper displacement (mm)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Scaled-down all-clump push: velocity and the clumps' rolling friction")
    fig.tight_layout()
    fig.savefig(os.path.join(here, "..", "..", "images", "lateral-push-small-rate.png"), dpi=120)


if __name__ == "__main__":
    main()
