"""Plots of one `legkit run` output folder: trajectory top view and error over time.

Usage: /usr/bin/python3 tools/plots/run_plots.py <folder> [--log LOG]
Reads the run's log (LOG, by default <folder>/log.csv) and every <folder>/estimate_<name>.csv and
writes <folder>/trajectory-top.png. When the log has ground truth (gt_*) it also writes
<folder>/errors.png, and, for the filters (estimates with sigma_* columns), <folder>/bounds.png
(position and velocity errors with their 3-sigma bounds) and <folder>/nees.png (NEES over time
with the single-run 95 % chi-square bounds). Without ground truth, <folder>/sigma.png shows the
filters' position and velocity standard deviations instead.
"""
import csv
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def has_column(path, column):
    with open(path, newline="", encoding="utf-8-sig") as f:
        header = next(line for line in f if not line.startswith("#"))
    return column in header.strip().split(",")


def nees_bounds(path):
    """(dof, lower, upper) from the '# nees_dof 9 lower .. upper ..' comment, or None."""
    with open(path) as f:
        first = f.readline().split()
    if len(first) == 7 and first[1] == "nees_dof":
        return int(first[2]), float(first[4]), float(first[6])
    return None


def read_csv(path, columns):
    """Returns {column: [floats]} for the requested columns; '#' comment lines are skipped."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        data = {c: [] for c in columns}
        for row in rows:
            for c in columns:
                data[c].append(float(row[c]))
    return data


def plot_without_truth(folder, estimates):
    """Trajectory and, for the filters, their standard deviations: all a log without truth gives."""
    fig, ax = plt.subplots(figsize=(7, 6))
    for name, e in estimates.items():
        ax.plot(e["px"], e["py"], lw=1, label=name)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Trajectory, top view (the log has no ground truth)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "trajectory-top.png"), dpi=120)
    filters = {}
    for name in estimates:
        path = os.path.join(folder, "estimate_" + name + ".csv")
        if has_column(path, "sigma_px"):
            filters[name] = read_csv(path, ["t", "sigma_px", "sigma_py", "sigma_vx", "sigma_vy"])
    if not filters:
        return
    fig, (ap, av) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for name, e in filters.items():
        ap.semilogy(e["t"], [math.hypot(a, b) for a, b in zip(e["sigma_px"], e["sigma_py"])],
                    lw=1, label=name)
        av.semilogy(e["t"], [math.hypot(a, b) for a, b in zip(e["sigma_vx"], e["sigma_vy"])],
                    lw=1, label=name)
    ap.set_ylabel("horizontal sigma_p [m]")
    av.set_ylabel("horizontal sigma_v [m/s]")
    av.set_xlabel("t [s]")
    for a in (ap, av):
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    ap.set_title("The filters' own uncertainty")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "sigma.png"), dpi=120)


def main(folder, log_path):
    estimates = {}
    for path in sorted(glob.glob(os.path.join(folder, "estimate_*.csv"))):
        name = os.path.basename(path)[len("estimate_"):-len(".csv")]
        estimates[name] = read_csv(path, ["t", "px", "py", "pz", "vx", "vy", "vz"])
    if not has_column(log_path, "gt_px"):
        plot_without_truth(folder, estimates)
        return
    truth = read_csv(log_path, ["t", "gt_px", "gt_py", "gt_pz", "gt_vx", "gt_vy", "gt_vz"])

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

    filters = {}
    for name in estimates:
        path = os.path.join(folder, "estimate_" + name + ".csv")
        if has_column(path, "sigma_px"):
            columns = ["t", "px", "py", "pz", "vx", "vy", "vz"] + \
                ["sigma_" + a for a in ("vx", "vy", "vz", "px", "py", "pz")]
            with_nees = has_column(path, "nees")
            filters[name] = (read_csv(path, columns + (["nees"] if with_nees else [])),
                             nees_bounds(path) if with_nees else None)
    if not filters:
        return
    every = max(1, len(truth["t"]) // 3000)  # thin to about 3000 points per curve
    fig, axes = plt.subplots(len(filters), 2, figsize=(11, 2.6 * len(filters)), squeeze=False,
                             sharex=True)
    colours = {"x": "tab:red", "y": "tab:green", "z": "tab:blue"}
    for row, (name, (e, _)) in enumerate(filters.items()):
        for col, (quantity, gt, unit) in enumerate((("p", "gt_p", "m"), ("v", "gt_v", "m/s"))):
            ax = axes[row][col]
            t = e["t"][::every]
            for axis, colour in colours.items():
                err = [e[quantity + axis][k] - truth[gt + axis][k]
                       for k in range(0, len(e["t"]), every)]
                bound = [3 * s for s in e["sigma_" + quantity + axis][::every]]
                ax.plot(t, err, color=colour, lw=0.7, label=axis + " error")
                ax.plot(t, bound, color=colour, lw=0.7, ls="--")
                ax.plot(t, [-b for b in bound], color=colour, lw=0.7, ls="--")
            ax.set_ylabel(f"{name}\n[{unit}]")
            ax.grid(True, alpha=0.3)
            if row == 0:
                ax.set_title(("Position" if quantity == "p" else "Velocity") +
                             " error (solid) and +-3 sigma (dashed)")
                ax.legend(loc="upper left", fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "bounds.png"), dpi=120)

    fig, ax = plt.subplots(figsize=(8, 4))
    for name, (e, bounds) in filters.items():
        if bounds is None:
            continue
        dof, lower, upper = bounds
        # NEES / dof, so that 9- and 6-dimensional filters share one axis (1 = consistent).
        ax.semilogy(e["t"][::every], [max(x / dof, 1e-4) for x in e["nees"][::every]], lw=0.6,
                    label=f"{name} (dof {dof}, 95 %: [{lower / dof:.2f}, {upper / dof:.2f}])")
    ax.axhline(1.0, color="k", lw=1)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("NEES / dof")
    ax.set_title("Consistency of one run (single-run 95 % bounds in the legend)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "nees.png"), dpi=120)


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 1:
        main(args[0], os.path.join(args[0], "log.csv"))
    elif len(args) == 3 and args[1] == "--log":
        main(args[0], args[2])
    else:
        sys.exit(__doc__)
