#!/usr/bin/python3
"""Figure for chapters/57.3-leg-kinematics.md: leg odometry on a trot turning in place.

Reads the CSV written by legkit-leg-odometry-figures and writes 57.3-leg-odometry.png into OUT:
  top     base velocity (x, y) from the stance feet with Go2 sensor noise, raw and averaged
          over 50 ms, against the truth (zero: the robot turns in place)
  bottom  noiseless error |v - v_true| with the correct formula and with the classic
          frame mix-up (body-frame J qdot used as a world-frame velocity)

    build/legkit-leg-odometry-figures /tmp/57.3.csv
    /usr/bin/python3 tools/plots/57.3-leg-odometry.py /tmp/57.3.csv chapters/figures

Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def moving_average(x, n):
    out, acc = [], 0.0
    for i, v in enumerate(x):
        acc += v
        if i >= n:
            acc -= x[i - n]
        out.append(acc / min(i + 1, n))
    return out


def main(path, out_dir):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    col = {k: [float(r[k]) for r in rows] for k in rows[0]}
    t = col["t"]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    for axis, colour in (("x", "tab:blue"), ("y", "tab:orange")):
        top.plot(t, col["lo_v" + axis], color=colour, alpha=0.25, lw=0.5,
                 label=f"leg odometry v_{axis}, per 1 kHz sample")
        top.plot(t, moving_average(col["lo_v" + axis], 50), color=colour, lw=1.5,
                 label=f"leg odometry v_{axis}, 50 ms average")
    top.plot(t, col["gt_vx"], "k--", lw=1, label="truth (v_x = v_y = 0)")
    top.set_ylabel("base velocity [m/s]")
    top.set_title("Trot turning in place at 0.5 rad/s, Go2 sensor noise")
    top.legend(fontsize=7, ncol=2, loc="upper left")
    top.grid(alpha=0.3)

    floor = 1e-18
    bottom.semilogy(t, [max(e, floor) for e in col["err_right"]], label="v = -R (w x r + J qdot)")
    bottom.semilogy(t, [max(e, floor) for e in col["err_wrong_frame"]],
                    label="frame mix-up: v = -(R (w x r) + J qdot)")
    bottom.set_xlabel("time [s]")
    bottom.set_ylabel("|v - v_true| [m/s], noiseless")
    bottom.legend(fontsize=8)
    bottom.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(f"{out_dir}/57.3-leg-odometry.png", dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: 57.3-leg-odometry.py DATA.csv OUT_DIR")
    main(sys.argv[1], sys.argv[2])
