"""Plots of one `legkit run` output folder: trajectory top view and error over time.

Usage: /usr/bin/python3 tools/plots/run_plots.py <folder>
Reads <folder>/log.csv (ground truth gt_*) and every <folder>/estimate_<name>.csv and writes
<folder>/trajectory-top.png and <folder>/errors.png.
"""
import csv
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path, columns):
    """Returns {column: [floats]} for the requested columns; '#' comment lines are skipped."""
    with open(path, newline="") as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        data = {c: [] for c in columns}
        for row in rows:
            for c in columns:
                data[c].append(float(row[c]))
    return data


def main(folder):
    truth = read_csv(os.path.join(folder, "log.csv"),
                     ["t", "gt_px", "gt_py", "gt_pz", "gt_vx", "gt_vy", "gt_vz"])
    estimates = {}
    for path in sorted(glob.glob(os.path.join(folder, "estimate_*.csv"))):
        name = os.path.basename(path)[len("estimate_"):-len(".csv")]
        estimates[name] = read_csv(path, ["t", "px", "py", "pz", "vx", "vy", "vz"])

    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(truth["gt_px"], truth["gt_py"], "k-", lw=2, label="ground truth")
    for name, e in estimates.items():
        ax.plot(e["px"], e["py"], lw=1, label=name)
    # Dead reckoning leaves the picture within seconds: frame the truth, not the worst estimate.
    span = max(max(truth["gt_px"]) - min(truth["gt_px"]), max(truth["gt_py"]) - min(truth["gt_py"]), 1.0)
    cx = 0.5 * (max(truth["gt_px"]) + min(truth["gt_px"]))
    cy = 0.5 * (max(truth["gt_py"]) + min(truth["gt_py"]))
    ax.set_xlim(cx - 0.75 * span, cx + 0.75 * span)
    ax.set_ylim(cy - 0.75 * span, cy + 0.75 * span)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Trajectory, top view")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "trajectory-top.png"), dpi=120)

    fig, (ap, av) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for name, e in estimates.items():
        ep = [math.dist((e["px"][k], e["py"][k], e["pz"][k]),
                        (truth["gt_px"][k], truth["gt_py"][k], truth["gt_pz"][k]))
              for k in range(len(e["t"]))]
        ev = [math.dist((e["vx"][k], e["vy"][k], e["vz"][k]),
                        (truth["gt_vx"][k], truth["gt_vy"][k], truth["gt_vz"][k]))
              for k in range(len(e["t"]))]
        ap.semilogy(e["t"], [max(x, 1e-6) for x in ep], lw=1, label=name)
        av.semilogy(e["t"], [max(x, 1e-6) for x in ev], lw=0.6, label=name)
    ap.set_ylabel("|position error| [m]")
    av.set_ylabel("|velocity error| [m/s]")
    av.set_xlabel("t [s]")
    for a in (ap, av):
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    ap.set_title("Errors against ground truth")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "errors.png"), dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
