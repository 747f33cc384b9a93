#!/usr/bin/python3
"""Figures for chapters/57.2-imu.md: gyro discretisation error and preintegration bias correction.

Reads the CSVs written by legkit-imu-figures into DIR and writes two PNGs into OUT:
  57.2-gyro-step-error.png      one-step error of R_k Exp(w_k dt) vs dt and vs impact severity
  57.2-bias-correction.png      first-order bias correction vs re-integration

    build/legkit-imu-figures build
    /usr/bin/python3 tools/plots/57.2-imu.py build chapters/figures

Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROFILES = {
    "impact_ramp": "landing ramp: +5 rad/s per ms",
    "gait_20Hz": "gait: 4 rad/s at 20 Hz",
    "ring_100Hz": "impact ringing: 6 rad/s at 100 Hz",
}


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def step_error(d, out):
    by = defaultdict(lambda: defaultdict(list))
    for r in rows(f"{d}/57.2-gyro-step-error.csv"):
        p = by[r["profile"]]
        for k in ("dt", "error_start", "error_midpoint"):
            p[k].append(float(r[k]))
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
    for i, (name, label) in enumerate(PROFILES.items()):
        c = f"C{i}"
        p = by[name]
        ms = [1e3 * t for t in p["dt"]]
        ax.loglog(ms, p["error_start"], "-", color=c, label=f"{label}, w sampled at step start")
        ax.loglog(ms, p["error_midpoint"], ":", color=c, label=f"{label}, w at mid-step")
    for f_hz, name in ((400, "400 Hz"), (1000, "1 kHz")):
        ax.axvline(1e3 / f_hz, color="gray", lw=0.8)
        ax.text(1e3 / f_hz, 0.80, name, rotation=90, fontsize=7, va="bottom",
                transform=ax.get_xaxis_transform())
    ax.set(xlabel="step dt [ms]", ylabel="one-step attitude error [rad]",
           title="Error of R$_{k+1}$ = R$_k$ Exp(w$_k$ dt) when w changes within the step")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6)

    imp = rows(f"{d}/57.2-gyro-impact.csv")
    alpha = [float(r["alpha"]) for r in imp]
    ax2.loglog(alpha, [float(r["error_400Hz"]) for r in imp], label="400 Hz (dt = 2.5 ms)")
    ax2.loglog(alpha, [float(r["error_1kHz"]) for r in imp], label="1 kHz (dt = 1 ms)")
    ax2.set(xlabel="angular acceleration during impact [rad/s$^2$]",
            ylabel="one-step attitude error [rad]",
            title="Start-sampled step: error = alpha dt$^2$ / 2")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out}/57.2-gyro-step-error.png", dpi=120)


def bias_correction(d, out):
    r = rows(f"{d}/57.2-bias-correction.csv")
    db = [float(x["db_norm"]) for x in r]
    fig, ax = plt.subplots(figsize=(6, 4.3))
    ax.loglog(db, [float(x["error_uncorrected"]) for x in r], "o-", ms=3,
              label="stale increments (bias change ignored)")
    ax.loglog(db, [float(x["error_corrected"]) for x in r], "o-", ms=3,
              label="first-order correction with the bias Jacobians")
    ax.set(xlabel="bias change |db| (gyro and accel stacked)",
           ylabel="error vs re-integration (9-vector norm)",
           title="Preintegration over 0.3 s: correction error is O(|db|$^2$)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out}/57.2-bias-correction.png", dpi=120)


if __name__ == "__main__":
    step_error(sys.argv[1], sys.argv[2])
    bias_correction(sys.argv[1], sys.argv[2])
