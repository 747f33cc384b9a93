#!/usr/bin/python3
"""Figures of `legkit study fusion` for chapters/57.8-exteroceptive-fusion.md.

  57.8-fusion-path.png   the circle walked: the truth, the simulated SLAM poses and each
                         coupling's estimate in the map frame (x, y)
  57.8-fusion-error.png  each coupling's position error and yaw error against time, with the
                         corridor (one axis unobserved by the poses) shaded and the loop
                         closure marked

    build/legkit study fusion --out /tmp/fusion            (draws them into /tmp/fusion)
    /usr/bin/python3 tools/plots/57.8-fusion.py /tmp/fusion [--out chapters/figures]

Reads <folder>/fusion-trace.csv, <folder>/fusion-poses.csv (when present) and
<folder>/summary.json. Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import argparse
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from palette import TRUTH, colour  # noqa: E402

# One colour per coupling (the couplings are not estimators of palette.py).
COUPLING_COLOURS = {
    "proprio": "tab:green",
    "loose": "tab:blue",
    "injection": "tab:orange",
    "smoother": "tab:red",
}


def coupling_colour(name):
    return COUPLING_COLOURS.get(name, colour(name))


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def mark_events(ax, summary):
    corridor = summary.get("corridor_s") or [None, None]
    if corridor[0] is not None and corridor[1] is not None and corridor[1] > corridor[0]:
        ax.axvspan(corridor[0], corridor[1], color="tab:gray", alpha=0.15, lw=0,
                   label="corridor")
    if summary.get("loop_closure_s") is not None:
        ax.axvline(summary["loop_closure_s"], color="tab:purple", ls="--", lw=1.0,
                   label="loop closure")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", help="output folder of legkit study fusion")
    parser.add_argument("--out", help="where to write the figures (default: the folder)")
    args = parser.parse_args()
    out = args.out or args.folder
    rows = read_csv(os.path.join(args.folder, "fusion-trace.csv"))
    if not rows:
        raise SystemExit(f"{args.folder}/fusion-trace.csv: no rows")
    with open(os.path.join(args.folder, "summary.json")) as f:
        summary = json.load(f)
    names = [c["name"] for c in summary["couplings"]]
    t = [float(r["t"]) for r in rows]

    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    poses_path = os.path.join(args.folder, "fusion-poses.csv")
    if os.path.exists(poses_path):
        poses = read_csv(poses_path)
        ax.plot([float(p["x"]) for p in poses], [float(p["y"]) for p in poses], ".",
                color="tab:gray", ms=1.5, alpha=0.5, label="SLAM poses (map frame)")
    ax.plot([float(r["gt_x"]) for r in rows], [float(r["gt_y"]) for r in rows],
            color=colour(TRUTH), lw=1.2, label=TRUTH)
    for name in names:
        ax.plot([float(r[f"{name}_x"]) for r in rows], [float(r[f"{name}_y"]) for r in rows],
                color=coupling_colour(name), lw=0.8, label=name)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"Physics trot around a circle, {summary['duration_s']:.0f} s, "
                 f"{summary['distance_m']:.0f} m")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "57.8-fusion-path.png"), dpi=120)

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ax in (top, bottom):
        mark_events(ax, summary)
    for name in names:
        top.plot(t, [float(r[f"{name}_err"]) for r in rows], color=coupling_colour(name), lw=0.8,
                 label=name)
        bottom.plot(t, [float(r[f"{name}_yaw_err_deg"]) for r in rows],
                    color=coupling_colour(name), lw=0.8, label=name)
    top.set_ylabel("position error [m]")
    top.set_yscale("log")
    top.set_title("Error against the truth (map frame)")
    top.legend(fontsize=8, loc="upper left")
    top.grid(alpha=0.3, which="both")
    bottom.set_ylabel("yaw error [deg]")
    bottom.set_xlabel("t [s]")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "57.8-fusion-error.png"), dpi=120)


if __name__ == "__main__":
    main()
