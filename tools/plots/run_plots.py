"""Plots of one `legkit run` output folder: trajectory top view and error over time.

Usage: /usr/bin/python3 tools/plots/run_plots.py <folder> [--log LOG]
Reads the run's log (LOG, by default <folder>/log.csv) and every <folder>/estimate_<name>.csv and
writes <folder>/trajectory-top.png. When the log has ground truth (gt_*) it also writes
<folder>/errors.png (position and velocity), <folder>/attitude.png (roll/pitch and yaw) and, for
the filters (estimates with sigma_* columns), <folder>/bounds.png (position and velocity errors
with their 3-sigma bounds) and <folder>/nees.png (NEES over time with the single-run 95 %
chi-square bounds). Without ground truth, <folder>/sigma.png shows the filters' position and
velocity standard deviations instead.

A real robot's truth may be pose-only (no gt_vx..gt_vz): the velocity errors are then taken
against the central difference of gt_p, as the run's table does (eval/metrics.hpp), and the
figures say so. Rows flagged gt_valid = 0 are left out of every error (NaN: the lines break there).

The estimate files may be thinned (`legkit run --estimate-rate`): each estimate is compared with
the log row nearest in time. Each estimator has one colour in every figure (palette.py).
"""
import glob
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

from palette import TRUTH, colour  # noqa: E402

VELOCITY_WINDOW = 1.0  # [s] of each RMS value in errors.png
DIFFERENCE_WINDOW = 0.05  # [s] of the central difference of a pose-only truth (eval::TruthOptions)


def header(path):
    """The column names of a CSV file whose header follows optional '#' comment lines."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        return next(line for line in f if not line.startswith("#")).strip().split(",")


def read_csv(path, columns=None):
    """{column: numpy array} for the requested columns (default: all)."""
    names = header(path)
    wanted = names if columns is None else columns
    with open(path, newline="", encoding="utf-8-sig") as f:
        next(line for line in f if not line.startswith("#"))  # past the header
        values = np.loadtxt(f, delimiter=",", comments="#", ndmin=2,
                            usecols=[names.index(c) for c in wanted])
    return {c: values[:, i] for i, c in enumerate(wanted)}


def central_difference(t, x, valid, window):
    """dx/dt on the valid rows, (x_b - x_a) / (t_b - t_a) with a, b the valid rows farthest apart in
    the window centred on the row (one-sided near the ends and dropouts, as eval::truthVelocity);
    NaN on the other rows and where no other valid row is in the window."""
    tv, xv = t[valid], x[valid]
    a = np.searchsorted(tv, tv - 0.5 * window, side="left")
    b = np.searchsorted(tv, tv + 0.5 * window, side="right") - 1
    out = np.full(len(t), np.nan)
    out[valid] = (xv[b] - xv[a]) / np.where(a < b, tv[b] - tv[a], np.nan)
    return out


def read_truth(path):
    """The log's ground truth {t, gt_p*, gt_q*, gt_v*, valid}, or None if it has none: valid is
    False on the rows flagged gt_valid = 0, whose gt_* are NaN. A pose-only truth's gt_v* is the
    central difference of its gt_p*."""
    names = header(path)
    if "gt_px" not in names:
        return None
    columns = ["gt_p" + a for a in "xyz"] + ["gt_q" + a for a in "wxyz"]
    if "gt_vx" in names:
        columns += ["gt_v" + a for a in "xyz"]
    truth = read_csv(path, ["t"] + columns + (["gt_valid"] if "gt_valid" in names else []))
    valid = truth.pop("gt_valid") != 0 if "gt_valid" in truth else np.full(len(truth["t"]), True)
    for c in columns:
        truth[c][~valid] = np.nan
    if "gt_vx" not in names:
        for a in "xyz":
            truth["gt_v" + a] = central_difference(truth["t"], truth["gt_p" + a], valid,
                                                   DIFFERENCE_WINDOW)
    truth["valid"] = valid
    return truth


def truth_notes(truth, differentiated):
    """(what the velocity errors are against, a line on the truth for the error figures or None)."""
    notes = []
    if differentiated:
        notes.append(f"velocity truth: differentiated gt_p (central difference over "
                     f"{DIFFERENCE_WINDOW:g} s; the log has no gt_v)")
    masked = np.sum(~truth["valid"])
    if masked:
        notes.append(f"{masked} log rows without truth (gt_valid = 0) left out")
    return ("differentiated gt_p" if differentiated else "ground truth"), "\n".join(notes) or None


def tilt_and_yaw(q):
    """Per quaternion (w, x, y, z) (rows of q, body to world): the world's up axis seen from the
    body (R^T z, whose angle between two attitudes is their roll/pitch error) and the heading
    atan2(R_10, R_00) [rad], as eval::tiltError and eval::yawError."""
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    up = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    return up, np.arctan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z))


def attitude_errors(q_hat, q):
    """(roll/pitch error, yaw error wrapped to [-180, 180)) [deg] of attitudes q_hat against q."""
    up_hat, yaw_hat = tilt_and_yaw(q_hat)
    up, yaw = tilt_and_yaw(q)
    tilt = np.arctan2(np.linalg.norm(np.cross(up_hat, up), axis=1), np.sum(up_hat * up, axis=1))
    return np.degrees(tilt), (np.degrees(yaw_hat - yaw) + 180.0) % 360.0 - 180.0


def nees_bounds(path):
    """(dof, lower, upper) from the '# nees_dof 9 lower .. upper ..' comment, or None."""
    with open(path) as f:
        first = f.readline().split()
    if len(first) == 7 and first[1] == "nees_dof":
        return int(first[2]), float(first[4]), float(first[6])
    return None


def nearest_rows(times, t):
    """Index of the entry of the sorted array times nearest to each t."""
    i = np.clip(np.searchsorted(times, t), 1, len(times) - 1)
    return np.where(np.abs(times[i - 1] - t) <= np.abs(times[i] - t), i - 1, i)


def rms_per_window(t, x, window):
    """(window centres, RMS of the finite x in each window [t0 + k w, t0 + (k + 1) w)) over windows
    with samples; NaN in one whose x are all NaN (a dropout of the truth: the line breaks there)."""
    k = np.floor((t - t[0]) / window).astype(int)
    finite = np.isfinite(x)
    sums = np.bincount(k[finite], weights=x[finite] ** 2, minlength=k[-1] + 1)
    counts = np.bincount(k[finite], minlength=k[-1] + 1)
    filled = np.bincount(k) > 0
    centres = t[0] + (np.arange(len(counts)) + 0.5) * window
    return centres[filled], np.sqrt(sums / np.where(counts > 0, counts, np.nan))[filled]


def off_frame(reference, paths):
    """Names of the paths ({name: (x, y)}) that stray from the reference (x, y, t-matched) by more
    than a quarter of its extent (at least 1 m): drawn at their own scale, they would squash the
    others into one line. A path must be finite throughout; the reference may have gaps (NaN: rows
    without truth), where nothing is compared."""
    rx, ry = reference
    known = np.isfinite(rx) & np.isfinite(ry)
    span = max(np.ptp(rx[known]), np.ptp(ry[known]), 4.0) if known.any() else 4.0
    far = set()
    for name, (x, y) in paths.items():
        distance = np.hypot(x - rx, y - ry)[known]
        if not np.all(np.isfinite(x) & np.isfinite(y)) or np.any(distance > 0.25 * span):
            far.add(name)
    return far


def frame(paths):
    """(xmin, xmax, ymin, ymax) around the paths ([(x, y)]) with a margin, at least 10 cm wide (a
    robot turning on the spot)."""
    x = np.concatenate([p[0] for p in paths])
    y = np.concatenate([p[1] for p in paths])
    x, y = x[np.isfinite(x)], y[np.isfinite(y)]
    half_x = max(0.55 * np.ptp(x), 0.05)
    half_y = max(0.55 * np.ptp(y), 0.05)
    cx, cy = 0.5 * (x.min() + x.max()), 0.5 * (y.min() + y.max())
    return cx - half_x, cx + half_x, cy - half_y, cy + half_y


def legend_outside(ax, **kwargs):
    """The legend to the right of the axes, off the data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **kwargs)


def save(fig, folder, name):
    fig.savefig(os.path.join(folder, name), dpi=120, bbox_inches="tight")
    plt.close(fig)


def draw_trajectory(folder, estimates, truth):
    """trajectory-top.png: zoomed on the truth (or, without it, on the estimators' median) and the
    estimators that follow it; one that strays (dead reckoning) is noted with where it ended and
    shown whole in the overview beside."""
    paths = {name: (e["px"], e["py"]) for name, e in estimates.items()}
    if truth is not None:
        reference_paths = {TRUTH: (truth["gt_px"], truth["gt_py"])}
        references = {name: (truth["gt_px"][r], truth["gt_py"][r])
                      for name, r in ((n, nearest_rows(truth["t"], e["t"]))
                                      for n, e in estimates.items())}
    else:
        reference_paths = {}
        lengths = {len(e["t"]) for e in estimates.values()}
        median = (np.median([p[0] for p in paths.values()], axis=0),
                  np.median([p[1] for p in paths.values()], axis=0)) if len(lengths) == 1 else None
        references = {name: median for name in estimates} if median is not None else {}
    far = set()
    for name, path in paths.items():
        if name in references:
            far |= off_frame(references[name], {name: path})
    near = {**reference_paths, **{n: p for n, p in paths.items() if n not in far}}
    if not near:
        near = paths

    fig = plt.figure(figsize=(11, 6))
    grid = fig.add_gridspec(2, 2, width_ratios=(3, 1), height_ratios=(1, 1))
    ax = fig.add_subplot(grid[:, 0])
    overview = fig.add_subplot(grid[0, 1])
    legend_box = fig.add_subplot(grid[1, 1])
    legend_box.axis("off")
    for a in (ax, overview):
        for name, (x, y) in reference_paths.items():
            a.plot(x, y, color=colour(name), lw=2, label=name)
        for name, (x, y) in paths.items():
            label = name
            if name in far:
                label = f"{name} (off the frame,\nends at x {x[-1]:.1f} m, y {y[-1]:.1f} m)"
            a.plot(x, y, color=colour(name), lw=1, label=label)
    xmin, xmax, ymin, ymax = frame(list(near.values()))
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    stretch = (xmax - xmin) / (ymax - ymin)
    if 0.25 <= stretch <= 4.0:
        ax.set_aspect("equal", adjustable="datalim")
        scale_note = ""
    else:
        scale_note = " (axes not to the same scale)"
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Trajectory, top view" + scale_note +
                 ("" if truth is not None else "\n(the log has no ground truth)"))
    ax.grid(True, alpha=0.3)
    overview.set_aspect("equal", adjustable="datalim")
    overview.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False, ls="--",
                                 lw=0.8, color="0.4"))
    overview.set_title("whole run (dashed: the frame)", fontsize=9)
    overview.tick_params(labelsize=7)
    overview.grid(True, alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    legend_box.legend(handles, labels, loc="upper left", fontsize=8, frameon=False)
    fig.tight_layout()
    save(fig, folder, "trajectory-top.png")


def draw_two_panels(folder, name, titles, ylabels, panels, note=None, log=True):
    """A figure of two panels (log-scale unless log is False) sharing time, each a list of
    (estimator, t, y, label), under the note if one is given."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for ax, title, ylabel, curves in zip(axes, titles, ylabels, panels):
        for estimator, t, y, label in curves:
            if log:
                ax.semilogy(t, np.maximum(y, 1e-6), color=colour(estimator), lw=1, label=label)
            else:
                ax.plot(t, y, color=colour(estimator), lw=1, label=label)
        ax.set_title(title, fontsize=10)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    legend_outside(axes[0])
    if note:
        fig.suptitle(note, fontsize=9)
    fig.tight_layout()
    save(fig, folder, name)


def draw_errors(folder, estimates, truth, velocity_truth, note):
    """errors.png: |position error| at each written sample, |velocity error| as its RMS per
    VELOCITY_WINDOW (every sample it would be a band of noise)."""
    position, velocity = [], []
    for name, e in estimates.items():
        r = nearest_rows(truth["t"], e["t"])
        ep = np.sqrt(sum((e["p" + a] - truth["gt_p" + a][r]) ** 2 for a in "xyz"))
        ev = np.sqrt(sum((e["v" + a] - truth["gt_v" + a][r]) ** 2 for a in "xyz"))
        position.append((name, e["t"], ep, name))
        t, rms = rms_per_window(e["t"], ev, VELOCITY_WINDOW)
        velocity.append((name, t, rms, name))
    draw_two_panels(folder, "errors.png",
                    ("Position error against ground truth, at each written sample",
                     f"Velocity error against {velocity_truth}, "
                     f"RMS over each {VELOCITY_WINDOW:g} s"),
                    ("|position error| [m]", "RMS |velocity error| [m/s]"), (position, velocity),
                    note)


def draw_attitude(folder, estimates, truth, note):
    """attitude.png: roll/pitch (tilt) and yaw errors at each written sample, as the run's table."""
    tilt, yaw = [], []
    for name, e in estimates.items():
        r = nearest_rows(truth["t"], e["t"])
        q_hat = np.stack([e["q" + a] for a in "wxyz"], axis=1)
        q = np.stack([truth["gt_q" + a][r] for a in "wxyz"], axis=1)
        e_tilt, e_yaw = attitude_errors(q_hat, q)
        tilt.append((name, e["t"], e_tilt, name))
        yaw.append((name, e["t"], e_yaw, name))
    draw_two_panels(folder, "attitude.png",
                    ("Roll/pitch error against ground truth: the angle between the up axes",
                     "Yaw error against ground truth, wrapped to [-180, 180)"),
                    ("roll/pitch error [deg]", "yaw error [deg]"), (tilt, yaw), note, log=False)


def draw_sigma(folder, filters):
    """sigma.png: the filters' own horizontal uncertainty, all a log without truth gives."""
    panels = ([(n, e["t"], np.hypot(e["sigma_px"], e["sigma_py"]), n) for n, e in filters.items()],
              [(n, e["t"], np.hypot(e["sigma_vx"], e["sigma_vy"]), n) for n, e in filters.items()])
    draw_two_panels(folder, "sigma.png",
                    ("The filters' own uncertainty: position", "... and velocity"),
                    ("horizontal sigma_p [m]", "horizontal sigma_v [m/s]"), panels)


def draw_bounds(folder, filters, truth, velocity_truth, note):
    """bounds.png: per filter, each axis's error (solid) inside its +-3 sigma (dashed)."""
    fig, axes = plt.subplots(len(filters), 2, figsize=(11, 2.6 * len(filters)), squeeze=False,
                             sharex=True)
    axis_colours = {"x": "tab:red", "y": "tab:green", "z": "tab:blue"}
    for row, (name, e) in enumerate(filters.items()):
        every = max(1, len(e["t"]) // 3000)  # about 3000 points per curve
        t = e["t"][::every]
        r = nearest_rows(truth["t"], t)
        for col, (quantity, unit) in enumerate((("p", "m"), ("v", "m/s"))):
            ax = axes[row][col]
            for a, c in axis_colours.items():
                err = e[quantity + a][::every] - truth["gt_" + quantity + a][r]
                bound = 3 * e["sigma_" + quantity + a][::every]
                ax.plot(t, err, color=c, lw=0.7, label=a + " error")
                ax.plot(t, bound, color=c, lw=0.7, ls="--")
                ax.plot(t, -bound, color=c, lw=0.7, ls="--")
            ax.set_ylabel(f"{name}\n[{unit}]", color=colour(name))
            ax.grid(True, alpha=0.3)
            if row == 0:
                ax.set_title(("Position" if quantity == "p" else "Velocity") +
                             " error (solid) and +-3 sigma (dashed)" +
                             (f"\nagainst {velocity_truth}" if quantity == "v" else ""))
    legend_outside(axes[0][1], fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    if note:
        fig.suptitle(note, fontsize=9)
    fig.tight_layout()
    save(fig, folder, "bounds.png")


def draw_nees(folder, filters, bounds):
    """nees.png: NEES / dof of each filter over the run, with its single-run 95 % bounds."""
    fig, ax = plt.subplots(figsize=(10, 4))
    for name, e in filters.items():
        dof, lower, upper = bounds[name]
        # NEES / dof, so that 9- and 6-dimensional filters share one axis (1 = consistent).
        ax.semilogy(e["t"], np.maximum(e["nees"] / dof, 1e-4), color=colour(name), lw=0.6,
                    label=f"{name} (dof {dof}, 95 %: [{lower / dof:.2f}, {upper / dof:.2f}])")
    ax.axhline(1.0, color="k", lw=1)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("NEES / dof")
    ax.set_title("Consistency of one run (single-run 95 % bounds in the legend)")
    ax.grid(True, which="both", alpha=0.3)
    legend_outside(ax, fontsize=8)
    fig.tight_layout()
    save(fig, folder, "nees.png")


def main(folder, log_path):
    estimates, bounds = {}, {}
    for path in sorted(glob.glob(os.path.join(folder, "estimate_*.csv"))):
        name = os.path.basename(path)[len("estimate_"):-len(".csv")]
        e = read_csv(path)
        if len(e["t"]) > 0:  # a run that failed at once has nothing to draw
            estimates[name] = e
            bounds[name] = nees_bounds(path)
    filters = {name: e for name, e in estimates.items() if "sigma_px" in e}
    truth = read_truth(log_path)
    draw_trajectory(folder, estimates, truth)
    if truth is None:
        if filters:
            draw_sigma(folder, filters)
        return
    velocity_truth, note = truth_notes(truth, "gt_vx" not in header(log_path))
    draw_errors(folder, estimates, truth, velocity_truth, note)
    draw_attitude(folder, estimates, truth, note)
    if filters:
        draw_bounds(folder, filters, truth, velocity_truth, note)
        with_nees = {n: e for n, e in filters.items() if "nees" in e and bounds[n] is not None}
        if with_nees:
            draw_nees(folder, with_nees, bounds)


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 1:
        main(args[0], os.path.join(args[0], "log.csv"))
    elif len(args) == 3 and args[1] == "--log":
        main(args[0], args[2])
    else:
        sys.exit(__doc__)
