#!/usr/bin/python3
"""Figure for chapters/57.1-role-of-estimation.md: how fast pure IMU integration drifts.

Reads 57.1-drift.csv written by legkit-imu-figures (a standing robot, readings synthesised by
model/imu_model.hpp, dead reckoning that ignores the bias) and draws position and attitude error
against time on log-log axes, with the chapter's table points marked.

    build/legkit-imu-figures build
    /usr/bin/python3 tools/plots/57.1-drift.py build/57.1-drift.csv chapters/figures/57.1-drift.png

Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {
    "accel_bias_0.01": "accelerometer bias 0.01 m/s$^2$",
    "gyro_bias_roll_0.01": "gyro bias 0.01 rad/s (roll axis)",
    "gyro_bias_yaw_0.01": "gyro bias 0.01 rad/s (yaw axis)",
    "accel_bias_0.01_go2_noise": "accel bias 0.01 + Go2 noise (one run)",
    "go2_noise_only": "Go2 noise only (one run)",
    "sim_stand_accel_bias_0.01": "simulator, swaying stand: accel bias 0.01",
    "sim_stand_gyro_bias_roll_0.01": "simulator, swaying stand: gyro bias 0.01 (roll)",
}


def read(path):
    data = defaultdict(lambda: defaultdict(list))
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t = float(row["t"])
            if t <= 0.0:
                continue
            d = data[row["case"]]
            for key in ("t", "position_error", "attitude_error_deg"):
                d[key].append(float(row[key]))
    return data


def main(csv_path, png_path):
    data = read(csv_path)
    fig, (ax_p, ax_r) = plt.subplots(1, 2, figsize=(11, 4.3))
    for i, (case, label) in enumerate(LABELS.items()):
        d = data[case]
        color = f"C{i}"
        style = {"gyro_bias_yaw_0.01": "-.", "go2_noise_only": ":"}.get(
            case, "--" if "noise" in case else "-")
        if case.startswith("sim_"):  # markers at log-spaced times, coloured like the still case
            style, color = "x", "C0" if "accel" in case else "C1"
            keep = sorted({min(range(len(d["t"])), key=lambda j: abs(d["t"][j] - 60 ** (k / 12)))
                           for k in range(-6, 13)})
            d = {key: [v[j] for j in keep] for key, v in d.items()}
        if any(p > 0 for p in d["position_error"]):
            ax_p.loglog(d["t"], d["position_error"], style, color=color, label=label)
        if any(a > 0 for a in d["attitude_error_deg"]):
            ax_r.loglog(d["t"], d["attitude_error_deg"], style, color=color, label=label)
    ax_p.plot([1, 10, 60], [0.005, 0.5, 18], "ko", mfc="none", label="chapter table (t$^2$)")
    ax_r.plot([60], [34.4], "ko", mfc="none", label="chapter: 34 deg at 60 s")
    ax_p.set_ylim(1e-5, 1e4)
    ax_p.set(xlabel="time [s]", ylabel="position error [m]",
             title="Position drift of dead reckoning (standing robot)")
    ax_r.set(xlabel="time [s]", ylabel="attitude error [deg]", title="Attitude drift")
    for ax in (ax_p, ax_r):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
