#!/usr/bin/python3
"""Figures of `legkit study contact` for chapters/57.6-contact-detection.md.

  57.6-contact-trace.png     one foot of the physics trot over 2 s: the foot sensor's force and the
                             true normal force with the Schmitt trigger's thresholds F_high and
                             F_low, and below it the true contact against what the Schmitt
                             trigger (and two other detectors) decided
  57.6-contact-f1-delay.png  F1 against the mean touchdown delay, one point per detector and
                             physics scenario

    build/legkit study contact --out /tmp/contact         (draws them into /tmp/contact)
    /usr/bin/python3 tools/plots/57.6-contact.py /tmp/contact [--out chapters/figures]

Reads <folder>/contact.csv and <folder>/contact-trace.csv. Run it with Debian's /usr/bin/python3
(python3-matplotlib).
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

# One colour per detector (the palette's spare colours are for estimators the kit does not know).
DETECTOR_COLOURS = {
    "gait-clock": "tab:gray",
    "grf-threshold": "tab:orange",
    "grf-threshold-torque": "tab:brown",
    "schmitt": "tab:blue",
    "schmitt-torque": "tab:cyan",
    "momentum-observer": "tab:purple",
    "probabilistic": "tab:green",
    "kinematic": "tab:olive",
    "fallback": "tab:red",
}
TRACE_DETECTORS = ("schmitt", "schmitt-torque", "probabilistic")


def detector_colour(name):
    return DETECTOR_COLOURS.get(name, colour(name))


def read(path):
    """The comment lines' text and the rows of a CSV written by legkit study."""
    with open(path, newline="") as f:
        lines = f.readlines()
    comments = " ".join(line[1:] for line in lines if line.startswith("#"))
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    return comments, rows


def number(comments, key, path):
    m = re.search(key + r" ([0-9.eE+-]+)", comments)
    if not m:
        raise SystemExit(f"{path}: no '{key}' in its comment line")
    return float(m.group(1))


def trace(folder, out):
    path = os.path.join(folder, "contact-trace.csv")
    comments, rows = read(path)
    f_high, f_low = number(comments, "f_high", path), number(comments, "f_low", path)
    foot = re.search(r"foot (\w+)", comments).group(1)
    t = [float(r["t"]) for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    top.plot(t, [float(r["force"]) for r in rows], color="tab:blue", lw=0.7,
             label=f"foot sensor force_{foot}")
    top.plot(t, [float(r["gt_fn"]) for r in rows], color=colour(TRUTH), lw=1.0,
             label="true normal force")
    top.axhline(f_high, color="tab:red", ls="--", lw=0.9, label=f"F_high = {f_high:g} N")
    top.axhline(f_low, color="tab:red", ls=":", lw=0.9, label=f"F_low = {f_low:g} N")
    top.set_ylabel("normal force [N]")
    top.set_title(f"Physics trot, foot {foot}: force and the Schmitt trigger's thresholds")
    top.legend(fontsize=8, loc="upper right")
    top.grid(alpha=0.3)
    names = ["gt_contact"] + [d for d in TRACE_DETECTORS if d in rows[0]]
    for level, name in enumerate(names):
        y = [1.2 * (len(names) - 1 - level) + 0.9 * float(r[name]) for r in rows]
        c = colour(TRUTH) if name == "gt_contact" else detector_colour(name)
        bottom.step(t, y, where="post", color=c, lw=1.0)
    bottom.set_yticks([1.2 * (len(names) - 1 - i) + 0.45 for i in range(len(names))])
    bottom.set_yticklabels(["truth" if n == "gt_contact" else n for n in names], fontsize=8)
    bottom.set_xlabel("t [s]")
    bottom.set_title("contact (high: in contact)", fontsize=9)
    bottom.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "57.6-contact-trace.png"), dpi=120)
    plt.close(fig)


def f1_delay(folder, out):
    path = os.path.join(folder, "contact.csv")
    _, rows = read(path)
    fig, ax = plt.subplots(figsize=(8, 5))
    seen = set()
    for r in rows:
        f1, delay = float(r["f1"]), float(r["touchdown_delay_mean_ms"])
        if math.isnan(f1) or math.isnan(delay):
            continue
        d = r["detector"]
        # The fallback chain answers with its first detector (the Schmitt trigger) whenever that
        # one can: a cross, so that the points it shares with "schmitt" stay visible.
        ax.scatter(delay, f1, color=detector_colour(d), s=40 if d == "fallback" else 22,
                   marker="x" if d == "fallback" else "o", label=None if d in seen else d)
        seen.add(d)
    ax.set_xlabel("mean touchdown delay [ms] (detected - true)")
    ax.set_ylabel("F1 (sample-wise, all feet)")
    ax.set_title("Contact detectors on the physics scenarios (one point per scenario)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "57.6-contact-f1-delay.png"), dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", help="output folder of legkit study contact")
    parser.add_argument("--out", help="where to write the figures (default: the folder)")
    args = parser.parse_args()
    out = args.out or args.folder
    trace(args.folder, out)
    f1_delay(args.folder, out)


if __name__ == "__main__":
    main()
