#!/usr/bin/python3
"""Figures of `legkit study` (chapters 57.4, 57.5 and 57.10).

Usage: /usr/bin/python3 tools/plots/study_plots.py <consistency|convergence|sweep> <folder>
Reads <folder>/<study>.csv written by `legkit study <study>` and writes <folder>/<study>.png.
Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from palette import colour  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def consistency(folder):
    data = defaultdict(lambda: {"t": [], "a": [], "dof": 1, "lo": 0, "hi": 0})
    for r in rows(f"{folder}/consistency.csv"):
        d = data[r["filter"]]
        d["t"].append(float(r["t"]))
        d["a"].append(float(r["anees"]) / int(r["dof"]))
        d["dof"], d["lo"], d["hi"] = int(r["dof"]), float(r["lower"]), float(r["upper"])
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name, d in data.items():
        ax.semilogy(d["t"], d["a"], color=colour(name), lw=0.8, label=f"{name} (dof {d['dof']})")
        ax.axhspan(d["lo"] / d["dof"], d["hi"] / d["dof"], color=colour(name), alpha=0.08)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("ANEES / dof")
    ax.set_title("Consistency over Monte Carlo runs of the trot (shaded: 95 % bounds)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{folder}/consistency.png", dpi=120)


def convergence(folder):
    data = defaultdict(lambda: {"angle": [], "fraction": [], "time": []})
    for r in rows(f"{folder}/convergence.csv"):
        d = data[r["filter"]]
        d["angle"].append(float(r["angle_deg"]))
        d["fraction"].append(100.0 * float(r["converged_fraction"]))
        d["time"].append(float(r["median_time_s"]) if r["median_time_s"] != "nan" else float("nan"))
    fig, (af, at) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for name, d in data.items():
        af.plot(d["angle"], d["fraction"], "o-", ms=3, color=colour(name), label=name)
        at.plot(d["angle"], d["time"], "o-", ms=3, color=colour(name), label=name)
    af.set_ylabel("runs converged [%]")
    at.set_ylabel("median time to converge [s]")
    at.set_xlabel("initial attitude error [deg]")
    af.set_title("Convergence from a wrong initial attitude")
    for a in (af, at):
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{folder}/convergence.png", dpi=120)


def sweep(folder):
    keys = ("scale", "position_rmse", "velocity_bias", "velocity_variance", "anees")
    data = defaultdict(lambda: {k: [] for k in keys})
    for r in rows(f"{folder}/sweep.csv"):
        d = data[r["parameter"]]
        for k in keys:
            d[k].append(float(r[k]))
    fig, axes = plt.subplots(3, len(data), figsize=(4 * len(data), 7.5), sharex=True,
                             squeeze=False)
    for col, (name, d) in enumerate(data.items()):
        bias2 = [b * b for b in d["velocity_bias"]]
        total = [b + v for b, v in zip(bias2, d["velocity_variance"])]
        ax = axes[0][col]
        lkf = colour("linear-kf")  # every curve is the linear KF's: told apart by style
        ax.loglog(d["scale"], bias2, "o-", ms=3, color=lkf, label="bias$^2$ (slow part)")
        ax.loglog(d["scale"], d["velocity_variance"], "s:", ms=3, color=lkf,
                  label="variance (fast part)")
        ax.loglog(d["scale"], total, "k--", lw=1, label="sum")
        ax.set_title(name, fontsize=9)
        axes[1][col].loglog(d["scale"], d["position_rmse"], "o-", ms=3, color=lkf)
        axes[2][col].loglog(d["scale"], d["anees"], "o-", ms=3, color=lkf)
        axes[2][col].axhline(1.0, color="k", lw=0.8)
        axes[2][col].set_xlabel("variance scale (x nominal)")
        for row in range(3):
            axes[row][col].grid(True, which="both", alpha=0.3)
            axes[row][col].axvline(1.0, color="grey", lw=0.8, ls=":")
    axes[0][0].legend(fontsize=7)
    axes[0][0].set_ylabel("velocity error [m$^2$/s$^2$]")
    axes[1][0].set_ylabel("position RMSE [m]")
    axes[2][0].set_ylabel("ANEES / dof")
    fig.suptitle("Linear KF: one noise variance scaled at a time (bias-variance trade-off)")
    fig.tight_layout()
    fig.savefig(f"{folder}/sweep.png", dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("consistency", "convergence", "sweep"):
        sys.exit(__doc__)
    {"consistency": consistency, "convergence": convergence, "sweep": sweep}[sys.argv[1]](sys.argv[2])
