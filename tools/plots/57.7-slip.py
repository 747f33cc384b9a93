#!/usr/bin/python3
"""Figure of `legkit study slip` for chapters/57.7-slip-and-terrain.md.

  57.7-slip.png  one foot on the ice patch (physics-ice, the naive controller): its true slip
                 speed, and the slip detector's Mahalanobis distance d2 of that foot's velocity
                 residual against the chi-square threshold chi2_3(0.99), with the rows where the
                 foot stands on ice shaded and the rows the detector calls slipping marked

    build/legkit study slip --out /tmp/slip               (draws it into /tmp/slip)
    /usr/bin/python3 tools/plots/57.7-slip.py /tmp/slip [--out chapters/figures]

Reads <folder>/slip-trace.csv. Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import argparse
import csv
import math
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from palette import TRUTH, colour  # noqa: E402

ICE = 0.3  # ground with a friction below this is shaded as ice


def spans(t, flags):
    """[begin, end) times of the runs of True in flags."""
    out, begin = [], None
    for ti, f in zip(t, flags):
        if f and begin is None:
            begin = ti
        if not f and begin is not None:
            out.append((begin, ti))
            begin = None
    if begin is not None:
        out.append((begin, t[-1]))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", help="output folder of legkit study slip")
    parser.add_argument("--out", help="where to write the figure (default: the folder)")
    args = parser.parse_args()
    path = os.path.join(args.folder, "slip-trace.csv")
    with open(path, newline="") as f:
        lines = f.readlines()
    comments = " ".join(line[1:] for line in lines if line.startswith("#"))
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    if not rows:
        raise SystemExit(f"{path}: no rows (the study traces physics-ice with invariant-ekf)")
    threshold = float(re.search(r"threshold ([0-9.eE+-]+)", comments).group(1))
    foot = re.search(r"foot (\w+)", comments).group(1)
    t = [float(r["t"]) for r in rows]
    ice = spans(t, [float(r["mu"]) < ICE for r in rows])
    slipping = spans(t, [r["slipping"] == "1" for r in rows])

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for ax in (top, bottom):
        for i, (a, b) in enumerate(ice):
            ax.axvspan(a, b, color="tab:cyan", alpha=0.12, lw=0,
                       label="foot on ice" if i == 0 else None)
    top.plot(t, [float(r["slip_speed"]) for r in rows], color=colour(TRUTH), lw=0.7,
             label=f"true slip speed of {foot}")
    top.axhline(0.1, color="tab:gray", ls=":", lw=0.9, label="0.1 m/s")
    top.set_ylabel("slip speed [m/s]")
    top.set_title(f"Physics trot over the ice patch, foot {foot}")
    top.legend(fontsize=8, loc="upper left")
    top.grid(alpha=0.3)
    d2 = [float(r["d2"]) for r in rows]
    bottom.semilogy(t, [x if not math.isnan(x) and x > 0 else float("nan") for x in d2],
                    color="tab:green", lw=0.7, label="d2 (stance rows)")
    bottom.axhline(threshold, color="tab:red", ls="--", lw=1.0,
                   label=f"chi2_3(0.99) = {threshold:.2f}")
    for i, (a, b) in enumerate(slipping):
        bottom.axvspan(a, b, ymin=0.0, ymax=0.04, color="tab:red", lw=0,
                       label="detected slipping" if i == 0 else None)
    bottom.set_ylabel("Mahalanobis distance d2")
    bottom.set_xlabel("t [s]")
    bottom.legend(fontsize=8, loc="upper left")
    bottom.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out or args.folder, "57.7-slip.png"), dpi=120)


if __name__ == "__main__":
    main()
