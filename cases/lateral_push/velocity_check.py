#!/usr/bin/env python3
"""Is a push quasi-static? Compares the same push run at two velocities (docs/validation.md,
"Push velocity: quasi-static"): the measure is the peak, which halving the velocity must
move by less than 5 %; the curve's other points say whether the whole curve moved.

Usage: velocity_check.py SLOW_DIR FAST_DIR   (results folders of the two runs, e.g.
       results/lateral_push/half-velocity/all-clump results/lateral_push/all-clump)
Prints, for each run and as the slow run's change against the fast one: the resistance (0.2 mm
running mean, as the summary's) at 0.5, 1, 2, 3 and 4 mm, the peak and its displacement, the
mean resistance over 1-5 mm, the part of it that reaches the walls over 1-5 mm (the rest is taken
by local damping and the inertia of the stones that move), and the summary's horizontal balance
error."""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from plot_push import read_push, running_mean  # noqa: E402

WINDOW = 0.0002  # m, the summary's smoothing window
AT_MM = [0.5, 1, 2, 3, 4]


def interpolated(d, y, x):
    """y at displacement x, linear between the first two rows about it (as the summary's)."""
    for k in range(1, len(d)):
        if d[k - 1] <= x <= d[k]:
            if d[k] == d[k - 1]:
                return y[k]
            return y[k - 1] + (y[k] - y[k - 1]) * (x - d[k - 1]) / (d[k] - d[k - 1])
    return float("nan")


def figures(folder):
    push = read_push(folder)
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    d, r = push["displacement_m"], push["resistance_n"]
    smooth = running_mean(d, r, WINDOW)
    peak = max(range(len(smooth)), key=lambda k: smooth[k])
    span = [k for k, x in enumerate(d) if 0.001 <= x <= 0.005]
    walls = [r[k] + push["wall_load_sum_n"][k] for k in span]
    out = {"%g mm" % x: interpolated(d, smooth, 1e-3 * x) for x in AT_MM}
    out["peak"] = smooth[peak]
    out["mean 1-5 mm"] = sum(r[k] for k in span) / len(span)
    out["walls 1-5 mm"] = sum(walls) / len(walls)
    return out, 1e3 * d[peak], summary


def main(slow_dir, fast_dir):
    slow, slow_at, slow_sum = figures(slow_dir)
    fast, fast_at, fast_sum = figures(fast_dir)
    print("%-14s %14s %14s %8s" % ("kN", "slow", "fast", "change"))
    for key in slow:
        change = 100.0 * (slow[key] / fast[key] - 1.0)
        print("%-14s %14.3f %14.3f %+7.1f %%" % (key, 1e-3 * slow[key], 1e-3 * fast[key], change))
    print("%-14s %11.2f mm %11.2f mm" % ("peak at", slow_at, fast_at))
    for key, label in (("push_velocity_m_s", "velocity, m/s"),
                       ("horizontal_balance_error", "balance error"), ("steps", "steps")):
        print("%-14s %14.4g %14.4g" % (label, slow_sum[key], fast_sum[key]))
    if slow_sum.get("push_velocity_m_s", 0) >= fast_sum.get("push_velocity_m_s", 0):
        print("velocity_check.py: warning: the first run is not the slower one")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
