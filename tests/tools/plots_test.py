"""The plot scripts' own logic (tools/plots): one colour per estimator, the trajectory framed on the
estimators that follow the truth, the velocity error as an RMS per window, thinned estimate files
matched to the log by time, the attitude errors, a pose-only truth with dropouts (gt_valid = 0),
and every figure of a run drawn from thinned files.

Run: LEGKIT=build/legkit /usr/bin/python3 tests/tools/plots_test.py  (ctest does this)
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                                "plots"))
import palette  # noqa: E402
import run_plots  # noqa: E402


class Palette(unittest.TestCase):
    def test_every_estimator_of_legkit_run_has_its_own_colour(self):
        legkit = os.environ.get("LEGKIT")
        if not legkit:
            self.skipTest("LEGKIT (the legkit program) not given")
        with tempfile.TemporaryDirectory() as out:
            result = subprocess.run([legkit, "run", "--duration", "0.2", "--no-plots", "--json",
                                     "--out", out], capture_output=True, text=True, check=True)
        names = [e["estimator"] for e in json.loads(result.stdout)]
        self.assertGreaterEqual(len(names), 6)
        for name in names:
            self.assertIn(name, palette.COLOURS, name + " has no colour of its own")
        colours = [palette.colour(n) for n in names + [palette.TRUTH]]
        self.assertEqual(len(set(colours)), len(colours), "two estimators share a colour")

    def test_an_unknown_estimator_always_gets_the_same_spare_colour(self):
        self.assertIn(palette.colour("my-filter"), palette.SPARE)
        self.assertEqual(palette.colour("my-filter"), palette.colour("my-filter"))


class Framing(unittest.TestCase):
    def test_dead_reckoning_is_off_the_frame_and_the_others_decide_it(self):
        t = np.linspace(0.0, 60.0, 601)
        truth = (0.5 * t, np.zeros_like(t))  # 30 m straight on
        follower = (0.5 * t, 0.005 * t)  # 0.3 m off at the end
        drifter = (0.5 * t - 0.03 * t**2, 0.03 * t**2)  # 100 m off at the end
        far = run_plots.off_frame(truth, {"eskf": follower, "imu-dead-reckoning": drifter})
        self.assertEqual(far, {"imu-dead-reckoning"})
        xmin, xmax, ymin, ymax = run_plots.frame([truth, follower])
        self.assertLess(xmin, 0.0)
        self.assertGreater(xmax, 30.0)
        self.assertLess(xmax - xmin, 40.0)  # not stretched to the drifter's 100 m
        self.assertLess(ymax - ymin, 2.0)
        self.assertGreater(ymax, 0.3)

    def test_a_path_that_stops_being_finite_is_off_the_frame(self):
        t = np.linspace(0.0, 1.0, 11)
        bad = (t.copy(), np.where(t > 0.5, np.nan, 0.0))
        self.assertEqual(run_plots.off_frame((t, 0 * t), {"x": bad}), {"x"})

    def test_a_truth_with_gaps_is_compared_where_it_is_known(self):
        t = np.linspace(0.0, 1.0, 11)
        truth = (t.copy(), np.where((t > 0.3) & (t < 0.6), np.nan, 0.0))
        self.assertEqual(run_plots.off_frame(truth, {"x": (t, 0 * t)}), set())


class Errors(unittest.TestCase):
    def test_rms_per_window(self):
        t = np.arange(2000) / 1000.0
        x = np.where(t < 1.0, 1.0, -3.0)
        centres, rms = run_plots.rms_per_window(t, x, 1.0)
        np.testing.assert_allclose(centres, [0.5, 1.5])
        np.testing.assert_allclose(rms, [1.0, 3.0])

    def test_a_window_without_truth_breaks_the_rms_line(self):
        t = np.arange(3000) / 1000.0
        x = np.where(t < 1.0, 1.0, np.where(t < 2.0, np.nan, 2.0))
        x[500] = np.nan  # and a single masked row elsewhere is left out of its window
        centres, rms = run_plots.rms_per_window(t, x, 1.0)
        np.testing.assert_allclose(centres, [0.5, 1.5, 2.5])
        np.testing.assert_allclose(rms, [1.0, np.nan, 2.0])

    def test_roll_pitch_and_wrapped_yaw_errors(self):
        def q(roll, yaw):  # [deg], R = Rz(yaw) Rx(roll)
            r, y = np.radians(roll) / 2, np.radians(yaw) / 2
            return [np.cos(y) * np.cos(r), np.cos(y) * np.sin(r), np.sin(y) * np.sin(r),
                    np.sin(y) * np.cos(r)]
        tilt, yaw = run_plots.attitude_errors(np.array([q(5, 100), q(0, 175), q(0, 180)]),
                                              np.array([q(0, 100), q(0, -175), q(0, 0)]))
        np.testing.assert_allclose(tilt, [5.0, 0.0, 0.0], atol=1e-6)
        np.testing.assert_allclose(yaw, [0.0, -10.0, -180.0], atol=1e-6)

    def test_a_pose_only_truth_is_differentiated_over_its_valid_rows(self):
        t = np.arange(101) / 100.0
        valid = (t < 0.4) | (t > 0.6)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "log.csv")
            with open(path, "w") as f:
                f.write("t,gt_px,gt_py,gt_pz,gt_qw,gt_qx,gt_qy,gt_qz,gt_valid\n")
                for k in range(len(t)):  # a dropout may hold any values: here a jump
                    x = 2.0 * t[k] if valid[k] else 50.0
                    f.write(f"{t[k]},{x},0,0.3,1,0,0,0,{int(valid[k])}\n")
            truth = run_plots.read_truth(path)
        np.testing.assert_array_equal(truth["valid"], valid)
        self.assertTrue(np.all(np.isnan(truth["gt_px"][~valid])))
        self.assertTrue(np.all(np.isnan(truth["gt_vx"][~valid])))
        np.testing.assert_allclose(truth["gt_vx"][valid], 2.0)  # one-sided beside the dropout
        np.testing.assert_allclose(truth["gt_vy"][valid], 0.0)

    def test_thinned_estimates_meet_the_log_row_of_their_time(self):
        log_t = 2.0 + np.arange(3001) / 1000.0
        kept = np.arange(0, 3001, 10)
        written = np.round(log_t[kept], 10) + 1e-11  # as printed with 10 digits
        np.testing.assert_array_equal(run_plots.nearest_rows(log_t, written), kept)


class Figures(unittest.TestCase):
    def test_every_figure_of_a_run_from_thinned_estimate_files(self):
        self.every_figure(pose_only=False)

    def test_every_figure_of_a_run_on_a_pose_only_truth_with_a_dropout(self):
        self.every_figure(pose_only=True)

    def every_figure(self, pose_only):
        rate, duration = 1000, 3.0
        t = np.arange(int(rate * duration) + 1) / rate
        gt = {"gt_px": 0.5 * t, "gt_py": 0 * t, "gt_pz": 0.3 + 0 * t,
              "gt_qw": 1 + 0 * t, "gt_qx": 0 * t, "gt_qy": 0 * t, "gt_qz": 0 * t}
        if pose_only:  # as a motion-capture log: no velocity, and 0.5 s without truth
            gt["gt_valid"] = np.where((t > 1.0) & (t < 1.5), 0, 1)
        else:
            gt.update({"gt_vx": 0.5 + 0 * t, "gt_vy": 0 * t, "gt_vz": 0 * t})
        with tempfile.TemporaryDirectory() as folder:
            with open(os.path.join(folder, "log.csv"), "w") as f:
                f.write("# a made-up log: only the columns the plots read\n")
                f.write("t," + ",".join(gt) + "\n")
                for k in range(len(t)):
                    f.write(f"{t[k]}," + ",".join(f"{gt[c][k]}" for c in gt) + "\n")
            every = 10  # 100 Hz, as `legkit run` writes by default
            sigma_cols = ["sigma_th" + a for a in "xyz"] + ["sigma_v" + a for a in "xyz"] + \
                ["sigma_p" + a for a in "xyz"]
            for name, drift in (("eskf", 0.01), ("imu-dead-reckoning", 20.0)):
                with open(os.path.join(folder, f"estimate_{name}.csv"), "w") as f:
                    filt = name == "eskf"
                    if filt:
                        f.write("# nees_dof 9 lower 2.7 upper 19.0\n")
                    f.write("t,px,py,pz,qw,qx,qy,qz,vx,vy,vz" +
                            ("," + ",".join(sigma_cols) + ",nees" if filt else "") + "\n")
                    for k in range(0, len(t), every):
                        row = [t[k], gt["gt_px"][k], drift * t[k] ** 2, 0.3, 1, 0, 0, 0,
                               0.5, 2 * drift * t[k], 0.0]
                        if filt:
                            row += [0.01] * 9 + [9.0]
                        f.write(",".join(f"{v:.10g}" for v in row) + "\n")
            run_plots.main(folder, os.path.join(folder, "log.csv"))
            for png in ("trajectory-top.png", "errors.png", "attitude.png", "bounds.png",
                        "nees.png"):
                path = os.path.join(folder, png)
                self.assertTrue(os.path.exists(path), png)
                self.assertGreater(os.path.getsize(path), 10000, png)


PLOTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "plots")
SOURCE = os.path.join(PLOTS, "..", "..")


class RealLogFigures(unittest.TestCase):
    def test_the_icub_log_pose_only_truth_with_dropouts_is_drawn(self):
        legkit = os.environ.get("LEGKIT")
        if not legkit:
            self.skipTest("LEGKIT (the legkit program) not given")
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([legkit, "run", "--log",
                            os.path.join(SOURCE, "data", "icub-walking", "walking.csv"),
                            "--config", os.path.join(SOURCE, "config", "robots", "icub.yaml"),
                            "--out", out], capture_output=True, check=True)
            with open(os.path.join(out, "summary.json")) as f:
                self.assertEqual(json.load(f)["plots"], "drawn")
            for png in ("trajectory-top.png", "errors.png", "attitude.png", "bounds.png"):
                self.assertGreater(os.path.getsize(os.path.join(out, png)), 10000, png)


class PhysicsFigures(unittest.TestCase):
    """Chapter 57.0's physics figures and table, drawn from short physics runs."""

    def setUp(self):
        self.legkit = os.environ.get("LEGKIT")
        if not self.legkit:
            self.skipTest("LEGKIT (the legkit program) not given")

    def sim(self, folder, scenario, duration):
        out = os.path.join(folder, scenario + ".csv")
        subprocess.run([self.legkit, "sim", "--scenario", scenario, "--duration", str(duration),
                        "--out", out], capture_output=True, check=True)
        return out

    def test_contact_forces_and_ice_slip(self):
        with tempfile.TemporaryDirectory() as folder:
            logs = [self.sim(folder, "physics-trot", 4.6), self.sim(folder, "physics-ice", 4.0),
                    self.sim(folder, "physics-ice-aware", 4.0)]
            done = subprocess.run([sys.executable, os.path.join(PLOTS, "57.0-physics-contacts.py")]
                                  + logs + [folder], capture_output=True, text=True, check=True)
            for png in ("57.0-contact-forces.png", "57.0-ice-slip.png"):
                path = os.path.join(folder, png)
                self.assertGreater(os.path.getsize(path), 10000, png)
            # The stance figures the chapter quotes, per foot of each log.
            self.assertEqual(done.stdout.count("touchdowns, peak slip median"), 12, done.stdout)
            # A log without the contact-truth columns is refused by name.
            subprocess.run([self.legkit, "sim", "--duration", "4.6", "--out",
                            os.path.join(folder, "analytic.csv")], capture_output=True, check=True)
            refused = subprocess.run([sys.executable,
                                      os.path.join(PLOTS, "57.0-physics-contacts.py"),
                                      os.path.join(folder, "analytic.csv")] + logs[1:] + [folder],
                                     capture_output=True, text=True)
            self.assertNotEqual(refused.returncode, 0)
            self.assertIn("no column gt_fn_FR", refused.stderr)

    def test_the_estimators_table_and_the_closed_loop(self):
        # 3.5 s: the push scenarios push at t = 3 s.
        done = subprocess.run([sys.executable, os.path.join(PLOTS, "57.0-physics-table.py"),
                               self.legkit, "--duration", "3.5", "--loop-duration", "1.5"],
                              capture_output=True, text=True, check=True)
        rows = [line for line in done.stdout.splitlines() if line.startswith("| `physics-")]
        self.assertEqual(len(rows), 5 * 10)  # five tables, ten physics scenarios
        self.assertIn("| truth |", done.stdout)
        self.assertIn("| invariant-ekf |", done.stdout)
        self.assertNotIn("nan", done.stdout)


if __name__ == "__main__":
    unittest.main()
