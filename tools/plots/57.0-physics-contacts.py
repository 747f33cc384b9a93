#!/usr/bin/python3
"""Figures for chapters/57.0-logs-and-simulator.md, drawn from two physics logs of `legkit sim`:

  57.0-contact-forces.png  one leg of a trot over a few gait cycles: the true normal contact force
                           (gt_fn_<leg>, from MuJoCo's contacts) against what the foot sensor
                           logs (force_<leg>: noisy, biased, saturating), and the true contact flag
  57.0-ice-slip.png        the sliding speed of each foot's contact point (gt_slip_<leg>) on the
                           trot across the ice patch (mu 0.1 under the right feet's path, from
                           x = 1 to 4 m), with the naive controller (it falls: the log ends
                           there) and with the friction-aware one

    build/legkit sim --scenario physics-trot --duration 6 --out /tmp/trot.csv
    build/legkit sim --scenario physics-ice --out /tmp/ice.csv          (exits 3: the robot falls)
    build/legkit sim --scenario physics-ice-aware --out /tmp/ice-aware.csv
    /usr/bin/python3 tools/plots/57.0-physics-contacts.py /tmp/trot.csv /tmp/ice.csv \
        /tmp/ice-aware.csv chapters/figures

It also prints, per foot, what the chapter quotes of the stance phases (after t = 3 s): the mean
velocity of the foot point, the slip speed of the contact point, the touchdown slip spikes.

Options: --leg FR (the leg of the force figure), --from 3 --to 4.5 (its time window [s]).
Run it with Debian's /usr/bin/python3 (python3-matplotlib).
"""
import argparse
import re

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from palette import SPARE, TRUTH, colour  # noqa: E402

LEGS = ("FL", "FR", "RL", "RR")
HIP_X = 0.1934  # the front hips ahead of the base origin [m] (model/quadruped.hpp)


def read_log(path):
    """The columns of a legkit log by name, as numpy arrays, and under "#duration" the duration
    the run asked for (from the comment legkit sim writes), if it says."""
    with open(path) as f:
        lines = f.readlines()
    comments = [line for line in lines if line.startswith("#")]
    lines = lines[len(comments):]
    names = lines[0].strip().split(",")
    data = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    log = {name: data[:, i] for i, name in enumerate(names)}
    for c in comments:
        m = re.search(r"duration ([0-9.eE+-]+) s", c)
        if m:
            log["#duration"] = float(m.group(1))
    return log


def need(log, names, path):
    missing = [n for n in names if n not in log]
    if missing:
        raise SystemExit(f"{path}: no column {missing[0]} (a physics log of legkit sim has it)")


def contact_forces(log, path, leg, t0, t1, out):
    need(log, ["t", "force_" + leg, "gt_fn_" + leg, "gt_contact_" + leg], path)
    t = log["t"]
    w = (t >= t0) & (t <= t1)
    if not w.any():
        raise SystemExit(f"{path}: no rows between t = {t0} and {t1} s")
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5), sharex=True,
                                      gridspec_kw={"height_ratios": [4, 1]})
    top.plot(t[w], log["force_" + leg][w], color=SPARE[0], lw=0.8,
             label=f"foot sensor force_{leg} (noise, bias, saturation)")
    top.plot(t[w], log["gt_fn_" + leg][w], color=colour(TRUTH), lw=1.2,
             label=f"true normal force gt_fn_{leg} (MuJoCo)")
    top.set_ylabel("normal force [N]")
    top.set_title(f"Physics trot, leg {leg}")
    top.legend(fontsize=8, loc="upper right")
    top.grid(alpha=0.3)
    bottom.step(t[w], log["gt_contact_" + leg][w], where="post", color=colour(TRUTH), lw=1)
    bottom.set_yticks([0, 1])
    bottom.set_ylabel("contact")
    bottom.set_xlabel("time [s]")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/57.0-contact-forces.png", dpi=120)
    plt.close(fig)


def ice_slip(runs, patch, out):
    """One panel per (title, log, path): the right feet's slip speed against the left feet's."""
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 2.8 * len(runs)), sharex=True,
                             squeeze=False)
    for ax, (title, log, path) in zip(axes[:, 0], runs):
        need(log, ["t", "gt_px"] + ["gt_slip_" + leg for leg in LEGS], path)
        t = log["t"]
        # The FR foot's nominal place, under its hip 0.1934 m ahead of the base origin.
        over = (log["gt_px"] + HIP_X >= patch[0]) & (log["gt_px"] + HIP_X <= patch[1])
        if over.any():
            ax.axvspan(t[over][0], t[over][-1], color="tab:cyan", alpha=0.15,
                       label=f"FR foot over the ice (x {patch[0]:g}..{patch[1]:g} m)")
        for leg in ("FL", "RL"):
            ax.plot(t, log["gt_slip_" + leg], color="tab:gray", lw=0.6, alpha=0.7,
                    label="FL, RL (left feet, off the ice)" if leg == "FL" else None)
        ax.plot(t, log["gt_slip_RR"], color="tab:red", lw=0.8, alpha=0.8, label="RR")
        ax.plot(t, log["gt_slip_FR"], color="tab:orange", lw=0.9, label="FR")
        duration = log.get("#duration")
        if duration is not None and t[-1] + 2e-3 < duration:  # stopped early: the robot fell
            ax.axvline(t[-1], color=colour(TRUTH), lw=1, ls=":")
            title += f": fell at t = {t[-1] + 1e-3:.2f} s"
        ax.set_title(title, fontsize=10)
        ax.set_ylabel("slip speed [m/s]")
        ax.legend(fontsize=7, loc="upper left")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(f"{out}/57.0-ice-slip.png", dpi=120)
    plt.close(fig)


def stance_stats(name, log, after=3.0):
    """Prints, per foot, over the rows after `after` seconds where the foot is in true contact:
    the stance fraction, the mean world velocity of the foot point (a rolling sphere's centre
    moves), the contact point's slip speed (mean, median) and, per touchdown, the peak slip of
    its first 30 ms and how long the slip stays above 0.05 m/s."""
    t = log["t"]
    print(f"{name}: in stance after t = {after:g} s")
    for leg in LEGS:
        contact = log["gt_contact_" + leg] > 0
        st = contact & (t > after)
        slip = log["gt_slip_" + leg]
        v = np.stack([log[f"gt_vf_{leg}_{a}"][st] for a in "xyz"], axis=1)
        downs = [k for k in np.flatnonzero(np.diff(contact.astype(int)) == 1) + 1 if t[k] > after]
        peaks = [slip[k:k + 30].max() for k in downs]
        above = [np.count_nonzero(slip[k:k + 100] > 0.05) for k in downs]
        print(f"  {leg}: stance {st.sum() / np.count_nonzero(t > after):.2f}, mean foot velocity "
              f"{np.array2string(v.mean(axis=0), precision=4)} m/s, slip mean "
              f"{slip[st].mean():.4f} median {np.median(slip[st]):.4f} m/s; "
              + (f"{len(downs)} touchdowns, peak slip median {np.median(peaks):.2f} m/s, "
                 f"above 0.05 m/s for {np.mean(above):.0f} rows" if downs else "no touchdown"))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("trot_log")
    p.add_argument("ice_log", help="physics-ice (the naive controller)")
    p.add_argument("ice_aware_log", help="physics-ice-aware")
    p.add_argument("out_dir")
    p.add_argument("--leg", default="FR", choices=LEGS)
    p.add_argument("--from", dest="t0", type=float, default=3.0)
    p.add_argument("--to", dest="t1", type=float, default=4.5)
    p.add_argument("--patch", type=float, nargs=2, default=(1.0, 4.0),
                   help="x range of the ice patch [m] (sim/physics_scenario.cpp)")
    a = p.parse_args()
    trot, ice, aware = read_log(a.trot_log), read_log(a.ice_log), read_log(a.ice_aware_log)
    contact_forces(trot, a.trot_log, a.leg, a.t0, a.t1, a.out_dir)
    ice_slip([("physics-ice, naive controller (plans with mu 0.6)", ice, a.ice_log),
              ("physics-ice-aware, |f_t| <= 0.08 f_n", aware, a.ice_aware_log)], a.patch,
             a.out_dir)
    for path, log in ((a.trot_log, trot), (a.ice_log, ice), (a.ice_aware_log, aware)):
        stance_stats(path, log)


if __name__ == "__main__":
    main()
