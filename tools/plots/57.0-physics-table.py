#!/usr/bin/python3
"""The estimators' table on physics logs for chapters/57.0-logs-and-simulator.md.

Runs `legkit run --scenario S --no-plots` (every estimator, the logged true contact flags) for the
analytic trot and every physics scenario at its own default length, and prints markdown tables:
position RMSE, velocity RMSE, roll/pitch and yaw RMSE, and the filters' ANEES, one row per
scenario (a robot that fell: the log up to the fall, said in the row). Then the closed loop
(exercise 57.X): `legkit sim --scenario physics-trot --duration 20 --closed-loop E` for every
estimator E, and what the robot really did with that estimate driving its controller (from the
log's ground truth, after t = 3 s, or over the second half of a shorter run).

    /usr/bin/python3 tools/plots/57.0-physics-table.py build/legkit [--duration S]

About 40 s on one core of the kit's machine.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

SCENARIOS = ["trot", "physics-stand", "physics-trot", "physics-turn", "physics-walk",
             "physics-push", "physics-step-down", "physics-slope", "physics-ice",
             "physics-ice-aware", "physics-ice-push"]
FILTERS = ["linear-kf", "eskf", "invariant-ekf", "tsif"]


def run(legkit, scenario, duration, out):
    command = [legkit, "run", "--scenario", scenario, "--no-plots", "--out", out]
    if duration:
        command += ["--duration", str(duration)]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode not in (0, 3):
        sys.exit(f"{' '.join(command)}: exit {done.returncode}\n{done.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def table(title, results, names, key, fmt):
    print(f"\n{title}\n")
    print("| scenario | " + " | ".join(names) + " |")
    print("| --- | " + " | ".join("---:" for _ in names) + " |")
    for scenario, summary in results:
        by_name = {e["estimator"]: e for e in summary["estimators"]}
        cells = []
        for n in names:
            value = by_name[n].get(key)
            cells.append("FAILED" if "failure" in by_name[n] else
                         "-" if value is None else fmt.format(value))
        label = f"`{scenario}`"
        if summary.get("fell"):
            label += " (fell at " + re.search(r"t = ([0-9.]+) s", summary["fell"]).group(1) + " s)"
        print(f"| {label} | " + " | ".join(cells) + " |")


def closed_loop(legkit, names, duration, tmp):
    print(f"\nClosed loop: physics-trot, {duration:g} s, the controller on each estimate\n")
    print("| controller's state | forward speed [m/s] | lateral speed [m/s] | height [m] | "
          "end position (x, y) [m] | outcome |")
    print("| --- | ---: | ---: | ---: | ---: | --- |")
    for name in [None] + names:
        out = os.path.join(tmp, f"loop-{name}.csv")
        command = [legkit, "sim", "--scenario", "physics-trot", "--duration", str(duration),
                   "--out", out]
        if name:
            command += ["--closed-loop", name]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode not in (0, 3):
            sys.exit(f"{' '.join(command)}: exit {done.returncode}\n{done.stderr}")
        with open(out) as f:
            lines = [line for line in f if not line.startswith("#")]
        header = lines[0].strip().split(",")
        data = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
        col = {n: data[:, i] for i, n in enumerate(header)}
        after = col["t"] > min(3.0, col["t"][-1] / 2)  # walking: after 3 s, or the second half
        outcome = "fell: " + done.stderr.split("fell at ")[1].split(";")[0] \
            if done.returncode == 3 else "walked"
        print(f"| {'truth' if name is None else name} | {col['gt_vx'][after].mean():.3f} | "
              f"{col['gt_vy'][after].mean():.3f} | {col['gt_pz'][after].min():.3f}-"
              f"{col['gt_pz'][after].max():.3f} | ({col['gt_px'][-1]:.2f}, "
              f"{col['gt_py'][-1]:.2f}) | {outcome} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("legkit")
    p.add_argument("--duration", type=float, help="for every scenario (default: each its own; "
                   "60 s for the analytic trot)")
    p.add_argument("--loop-duration", type=float, default=20.0,
                   help="length of each closed-loop run [s]")
    a = p.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for s in SCENARIOS:
            results.append((s, run(a.legkit, s, a.duration, os.path.join(tmp, s))))
        names = [e["estimator"] for e in results[0][1]["estimators"]]
        table("Position RMSE [m]", results, names, "position_rmse_m", "{:.3f}")
        table("Velocity RMSE [m/s]", results, names, "velocity_rmse_mps", "{:.3f}")
        table("Roll/pitch RMSE [deg]", results, names, "roll_pitch_rmse_deg", "{:.2f}")
        table("Yaw RMSE [deg]", results, names, "yaw_rmse_deg", "{:.2f}")
        table("ANEES (about 1 when consistent)", results, FILTERS, "anees", "{:.2f}")
        closed_loop(a.legkit, names, a.loop_duration, tmp)


if __name__ == "__main__":
    main()
