#!/usr/bin/python3
"""Figure of `legkit allan` (chapters/57.10-allan-variance.md): the Allan deviation of each axis.

Reads allan.csv (axis, tau, m, adev, lo, hi) and allan-lines.csv (the fitted -1/2 and +1/2 lines
and the minimum) from the command's output folder and draws two log-log panels, gyro and
accelerometer: each axis's curve with its 1-sigma band, the fitted lines over the whole tau range
(solid where the points they were fitted to lie), the readings N_w at tau = 1 s and K at tau = 3 s,
and the minimum.

    build/legkit allan --simulate 7200 --out build/allan-go2
    /usr/bin/python3 tools/plots/57.10-allan.py build/allan-go2 [chapters/figures/57.10-allan.png]

Writes <folder>/allan.png, or the second argument. Run it with Debian's /usr/bin/python3
(python3-matplotlib).
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"x": "tab:red", "y": "tab:green", "z": "tab:blue"}
SENSORS = (("gyro", "gyro [rad/s]", "rad/s/$\\sqrt{Hz}$", "rad/s$^2$/$\\sqrt{Hz}$"),
           ("acc", "accelerometer [m/s$^2$]", "m/s$^2$/$\\sqrt{Hz}$", "m/s$^3$/$\\sqrt{Hz}$"))


def number(text):
    return math.nan if text in ("-", "") else float(text)


def read(folder):
    curves = defaultdict(lambda: defaultdict(list))
    with open(os.path.join(folder, "allan.csv"), newline="") as f:
        for row in csv.DictReader(f):
            c = curves[row["axis"]]
            for key in ("tau", "adev", "lo", "hi"):
                c[key].append(float(row[key]))
    lines = defaultdict(dict)
    with open(os.path.join(folder, "allan-lines.csv"), newline="") as f:
        for row in csv.DictReader(f):
            lines[row["axis"]][row["line"]] = {k: number(v) for k, v in row.items()
                                               if k not in ("axis", "line")}
    return curves, lines


def draw_line(ax, line, taus, colour):
    """The fitted line: dotted over the whole range, solid over the points it was fitted to."""
    if math.isnan(line["level"]):
        return
    level, slope, tau_read = line["level"], line["slope"], line["tau_read"]

    def at(t):
        return level * (t / tau_read) ** slope

    ax.plot(taus, [at(t) for t in taus], ":", color=colour, lw=0.8)
    used = [t for t in taus if line["tau_first"] <= t <= line["tau_last"]]
    ax.plot(used, [at(t) for t in used], "-", color=colour, lw=2.2, alpha=0.45)
    ax.plot([tau_read], [level], "o", color=colour, ms=6, mfc="white")


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: 57.10-allan.py FOLDER [OUTPUT.png]")
    folder = sys.argv[1]
    output = sys.argv[2] if len(sys.argv) == 3 else os.path.join(folder, "allan.png")
    curves, lines = read(folder)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, (sensor, title, white_unit, walk_unit) in zip(axes, SENSORS):
        notes = []
        for axis in ("x", "y", "z"):
            name = sensor + "_" + axis
            if name not in curves:
                continue
            c, colour = curves[name], COLOURS[axis]
            ax.fill_between(c["tau"], c["lo"], c["hi"], color=colour, alpha=0.15, lw=0)
            ax.plot(c["tau"], c["adev"], ".-", color=colour, ms=3, lw=1, label=name)
            fitted = lines[name]
            draw_line(ax, fitted["white"], c["tau"], colour)
            draw_line(ax, fitted["random_walk"], c["tau"], colour)
            minimum = fitted["bias_instability"]
            if not math.isnan(minimum["tau_read"]):
                ax.plot([minimum["tau_read"]], [minimum["level"]], "v", color=colour, ms=7)
            notes.append("%s: N %.3g, K %.3g" % (name, fitted["white"]["level"],
                                                 fitted["random_walk"]["level"]))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("averaging time $\\tau$ [s]")
        ax.set_ylabel("Allan deviation $\\sigma(\\tau)$")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
        ax.text(0.02, 0.02, "\n".join(notes) + "\nN in %s (o at 1 s), K in %s (o at 3 s),"
                "\n$\\triangledown$ minimum (B = min / 0.664)" % (white_unit, walk_unit),
                transform=ax.transAxes, fontsize=7, va="bottom")
    fig.suptitle("Overlapping Allan deviation with 1-sigma bands; the -1/2 and +1/2 lines")
    fig.tight_layout()
    fig.savefig(output, dpi=110)


if __name__ == "__main__":
    main()
