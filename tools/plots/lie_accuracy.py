#!/usr/bin/python3
"""Figure for chapters/00-lie-groups.md: accuracy of the angle coefficients that cancel.

Reads the CSV written by `legkit lie-accuracy --csv FILE` and draws, on log-log axes, the
relative error of each coefficient evaluated naively and by lie::AngleSeries, with lie's Taylor
switch points marked.

    build/legkit lie-accuracy --points 1500 --csv build/lie_accuracy.csv
    /usr/bin/python3 tools/plots/lie_accuracy.py build/lie_accuracy.csv \
        chapters/figures/lie-coefficient-accuracy.png

Run it with Debian's /usr/bin/python3 (python3-matplotlib), not another python3 on PATH.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-18  # errors below this (lie is often exact) are drawn on the floor
UNIT_ROUNDOFF = 2.0**-53


def read(path):
    switches, header, rows = {}, None, []
    with open(path, newline="") as f:
        for line in f:
            if line.startswith("# switch"):
                _, _, name, value = line.split()
                switches[name] = float(value)
            elif line.startswith("#"):
                continue
            elif header is None:
                header = next(csv.reader([line]))
            else:
                rows.append([float(v) for v in next(csv.reader([line]))])
    cols = {name: [r[i] for r in rows] for i, name in enumerate(header)}
    return cols, switches


def draw(ax, theta, curves):
    for label, values, style in curves:
        ys = [max(v, FLOOR) for v in values]
        if style.endswith("."):  # naive forms: dots, since they jump between 1 and huge values
            ax.plot(theta, ys, style, label=label, ms=2.5)
        else:
            ax.plot(theta, ys, style, label=label, lw=1.2)
    ax.axhline(UNIT_ROUNDOFF, color="0.4", ls=":", lw=1, label="unit roundoff 1.1e-16")


def mark(ax, switches):
    for name, (theta_s, color) in switches.items():
        ax.axvline(theta_s, color=color, ls="--", lw=1.2, label=f"{name} series → closed form, θ = {theta_s:g}")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: lie_accuracy.py IN.csv OUT.png")
    cols, sw = read(sys.argv[1])
    theta = cols["theta"]
    g3 = ("G₃ naive (θ − sin θ)/θ³", cols["g3_naive"], "C3.")
    g4 = ("G₄ naive (θ²/2 + cos θ − 1)/θ⁴", cols["g4_naive"], "C1.")
    g3l = ("G₃ lie::AngleSeries", cols["g3_lie"], "C0-")
    g4l = ("G₄ lie::AngleSeries", cols["g4_lie"], "C2-")
    cq = ("(G₄−3G₅)/2 naive (2θ − 3 sin θ + θ cos θ)/(2θ⁵)", cols["cq_naive"], "C5.")
    cql = ("(G₄−3G₅)/2 lie::AngleSeries", cols["cq_lie"], "C9-")

    fig = plt.figure(figsize=(13, 9.5))
    grid = fig.add_gridspec(2, 2, height_ratios=[1.0, 0.8])
    a, b = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    c = fig.add_subplot(grid[1, :])
    for ax in (a, b):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1e-10, 3.5)
    draw(a, theta, [g3, g4, g3l, g4l])
    mark(a, {"G₃": (sw["G3"], "C0"), "G₄": (sw["G4"], "C2")})
    a.set_ylim(FLOOR / 3, 1e3)
    a.set_title("(a) G₃, G₄ (in Jr, Jl⁻¹, Γ₁, Γ₂)", fontsize=10)

    draw(b, theta, [cq, cql])
    mark(b, {"G₄": (sw["G4"], "C2"), "G₅": (sw["G5"], "C4")})
    b.set_ylim(FLOOR / 3, 1e27)
    b.set_title("(b) (G₄ − 3G₅)/2, the cancelling coefficient of SE(3)'s Q", fontsize=10)

    zoom = [i for i, t in enumerate(theta) if t >= 0.2]
    sub = lambda cv: (cv[0], [cv[1][i] for i in zoom], cv[2])  # noqa: E731
    draw(c, [theta[i] for i in zoom], [sub(x) for x in (g3, g4, cq, g3l, g4l, cql)])
    mark(c, {"G₃": (sw["G3"], "C0"), "G₄": (sw["G4"], "C2"), "G₅": (sw["G5"], "C4")})
    c.set_yscale("log")
    c.set_xlim(0.2, 3.2)
    c.set_ylim(1e-18, 1e-11)
    c.set_title("(c) zoom on θ from 0.2 to π (linear axis): each switch sits where the closed form "
                "has become as accurate as the series", fontsize=10)

    for ax in (a, b, c):
        ax.set_xlabel("rotation angle θ [rad]" + (" (linear)" if ax is c else ""))
        ax.set_ylabel("relative error vs long-double series")
        ax.grid(True, which="major", color="0.9")
    a.legend(loc="upper right", fontsize=7.5)
    b.legend(loc="upper right", fontsize=7.5)
    c.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5)
    fig.suptitle("Closed forms that subtract nearly equal numbers lose every digit as θ → 0;\n"
                 "lie/ sums a Taylor series below each switch point and stays near roundoff "
                 "(errors below 1e-18, often exactly 0, are drawn at 1e-18)", fontsize=11)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
