#!/usr/bin/python3
"""The estimators' table on physics logs for chapters/57.0-logs-and-simulator.md.

Runs `legkit run --scenario S --no-plots` (every estimator, the logged true contact flags) for the
analytic trot and every physics scenario at its own default length, and prints markdown tables:
position RMSE, velocity RMSE, roll/pitch and yaw RMSE, and the filters' ANEES, one row per
scenario (a robot that fell: the log up to the fall, said in the row).

    /usr/bin/python3 tools/plots/57.0-physics-table.py build/legkit [--duration S]

About a minute on one core of the kit's machine.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

SCENARIOS = ["trot", "physics-stand", "physics-trot", "physics-turn", "physics-walk",
             "physics-push", "physics-step-down", "physics-ice", "physics-ice-aware",
             "physics-ice-push"]
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


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("legkit")
    p.add_argument("--duration", type=float, help="for every scenario (default: each its own; "
                   "60 s for the analytic trot)")
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


if __name__ == "__main__":
    main()
