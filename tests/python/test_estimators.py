"""legkit.estimators: the same estimators as the command line, step by step and over a whole log."""
import csv
import json
import subprocess

import numpy as np
import pytest

import legkit
from conftest import ICUB_CONFIG, ICUB_LOG, LEGKIT

est = legkit.estimators
G = np.array([0.0, 0.0, 9.81])  # the kit's g (model/imu_model.hpp)
STANCE = [np.array([0.19, 0.11, -0.3]), np.array([0.19, -0.11, -0.3]),
          np.array([-0.19, 0.11, -0.3]), np.array([-0.19, -0.11, -0.3])]


def feet():
    return [est.ContactMeasurement(k, p, 1e-6 * np.eye(3), v_body=np.zeros(3))
            for k, p in enumerate(STANCE)]


def test_names_in_the_chapters_order():
    assert est.names() == ["imu-dead-reckoning", "leg-odometry", "linear-kf", "eskf",
                           "invariant-ekf", "tsif"]


@pytest.mark.parametrize("name", est.names())
def test_every_estimator_holds_a_standing_robot(name):
    e = est.make(name)
    assert e.name == name
    e.reset(est.EstimateSample())
    for k in range(500):
        e.step(k * 1e-3, 1e-3 if k else 0.0, np.zeros(3), G, feet())
    x = e.estimate()
    assert x.t == pytest.approx(0.499)
    assert np.linalg.norm(x.p) < 1e-3 and np.linalg.norm(x.v) < 1e-3
    assert np.allclose(x.R, np.eye(3), atol=1e-6)
    P = e.covariance()
    if name in ("imu-dead-reckoning", "leg-odometry"):
        assert P is None
    else:
        cov, has_attitude = P
        assert cov.shape == (9, 9) and np.allclose(cov, cov.T)
        assert has_attitude == (name != "linear-kf")
        assert np.all(np.linalg.eigvalsh(cov[3:, 3:]) > 0)
    assert e.health() == {}


def run_cli(tmp_path, *args):
    out = tmp_path / "cli"
    subprocess.run([str(LEGKIT), "run", *args, "--estimate-rate", "all", "--no-plots", "--out",
                    str(out)], check=True, capture_output=True)
    return out


def read_estimates(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header = rows[0]
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(header)}


def test_run_is_legkit_run_on_a_real_robots_log(tmp_path):
    """The iCub log through the robot's URDF, the front end and every estimator: the arrays are
    the C++ run's to the 10 significant digits its estimate files carry."""
    log = legkit.io.read_log(str(ICUB_LOG))
    runs = est.run(log, est.load_settings(str(ICUB_CONFIG)))
    out = run_cli(tmp_path, "--dataset", "icub-walking")
    assert list(runs) == est.names()
    for name, r in runs.items():
        cli = read_estimates(out / f"estimate_{name}.csv")
        assert r["healthy"] and r["failure"] is None, name
        # icub.yaml starts every gyro bias from the still window, as the CLI's start: line says.
        assert r["start"].startswith("gyro bias [")
        assert r["start"] == json.loads((out / "summary.json").read_text())["start"]["note"]
        assert np.array_equal(r["t"], log["t"])
        np.testing.assert_allclose(cli["t"], log["t"], rtol=1e-9)
        for key, cols in (("p", "pxyz"), ("v", "vxyz")):
            for i, c in enumerate(cols[1:]):
                np.testing.assert_allclose(r[key][:, i], cli[cols[0] + c], rtol=1e-9, atol=1e-12)
        q = r["q"] * np.sign(r["q"][:, :1])
        qc = np.stack([cli["qw"], cli["qx"], cli["qy"], cli["qz"]], axis=1)
        np.testing.assert_allclose(q, qc * np.sign(qc[:, :1]), rtol=1e-9, atol=1e-12)
        if r["sigma"] is not None:
            np.testing.assert_allclose(r["sigma"][:, 6], cli["sigma_px"], rtol=1e-9)
            np.testing.assert_allclose(r["nees"], cli["nees"], rtol=1e-9)


def test_run_on_a_simulated_trot_is_consistent(trot_log):
    runs = est.run(trot_log, legkit.sim.settings_for("trot"), estimators=["eskf", "invariant-ekf"])
    assert list(runs) == ["eskf", "invariant-ekf"]
    for r in runs.values():
        assert r["start"] is None  # the simulated trot's settings start every gyro bias at zero
        n = len(trot_log)
        assert r["p"].shape == (n, 3) and r["q"].shape == (n, 4) and r["sigma"].shape == (n, 9)
        assert r["contacts"].shape == (n, 4) and r["contact_source"] == "truth"
        assert r["nees_dof"] == 9
        anees = np.nanmean(r["nees"]) / 9
        assert 0.2 < anees < 3.0, anees


def test_settings_from_yaml_and_its_errors(tmp_path):
    s = est.settings_from_yaml("estimators: [eskf]\n")
    assert s.estimators == ["eskf"]
    assert "estimators:" in s.yaml()
    with pytest.raises(est.SettingsError, match="mine.yaml:1: no_such_key: unknown key"):
        est.settings_from_yaml("no_such_key: 1\n", "mine.yaml")
    with pytest.raises(ValueError, match="missing.yaml"):
        est.load_settings(str(tmp_path / "missing.yaml"))
    icub = est.load_settings(str(ICUB_CONFIG))
    changed = icub.updated("contact: {settle_time: 0.02}\nestimators: [eskf]")
    assert changed.estimators == ["eskf"] and "settle_time: 0.02" in changed.yaml()
    assert "root_link" in changed.yaml()  # the robot section kept
    assert icub.yaml() != changed.yaml() and icub.estimators != ["eskf"]
    with pytest.raises(est.SettingsError, match=r"mine:2: contact.nope: unknown key"):
        icub.updated("contact:\n  nope: 1\n", "mine")


def test_bad_input_is_an_exception_with_the_cpp_message():
    e = est.make("invariant-ekf")
    e.reset(est.EstimateSample())
    e.step(0.0, 0.0, np.zeros(3), G)
    with pytest.raises(ValueError, match=r"t = 0.001.*w_m is not finite"):
        e.step(1e-3, 1e-3, np.array([np.nan, 0, 0]), G)
    with pytest.raises(ValueError, match=r"gyro: expected shape \(3,\), got \(4,\)"):
        e.step(1e-3, 1e-3, np.zeros(4), G)
    with pytest.raises(TypeError, match="gyro: expected a float64 array, got dtype float32"):
        e.step(1e-3, 1e-3, np.zeros(3, dtype=np.float32), G)
    with pytest.raises(TypeError, match="acc: expected a float64 array or numbers"):
        e.step(1e-3, 1e-3, np.zeros(3), ["a", "b", "c"])
    not_spd = [est.ContactMeasurement(0, STANCE[0], -np.eye(3))]
    with pytest.raises(ValueError, match="positive definite"):
        e.step(1e-3, 1e-3, np.zeros(3), G, not_spd)
    with pytest.raises(ValueError, match="known: imu-dead-reckoning"):
        est.make("no-such-filter")
    with pytest.raises(ValueError, match="unit quaternion"):
        est.EstimateSample(q=[2.0, 0, 0, 0])
    # Nothing changed: the rejected samples left the filter where it was.
    assert e.estimate().t == 0.0 and e.health() == {}


def test_the_manager_runs_a_log_sample_by_sample(trot_log):
    settings = est.settings_from_yaml(
        "estimators: [invariant-ekf]\ncontact:\n  detector: truth\n  settle_time: 0\n"
        "  rolling_foot: false\ninitialisation:\n  enabled: false\n")
    manager = est.StateEstimator(settings)
    assert manager.estimator == "invariant-ekf" and manager.contact_source == "truth"
    assert manager.num_joints == 12 and manager.num_feet == 4
    c = trot_log.to_dict()
    legs = ["FL", "FR", "RL", "RR"]
    q = np.stack([c[f"q_{leg}_{j}"] for leg in legs for j in range(3)], axis=1)
    dq = np.stack([c[f"dq_{leg}_{j}"] for leg in legs for j in range(3)], axis=1)
    force = np.stack([c[f"force_{leg}"] for leg in legs], axis=1)
    contact = np.stack([c[f"contact_{leg}"] for leg in legs], axis=1) > 0.5
    gyro = np.stack([c["gyro_x"], c["gyro_y"], c["gyro_z"]], axis=1)
    acc = np.stack([c["acc_x"], c["acc_y"], c["acc_z"]], axis=1)
    truth = np.stack([c["gt_px"], c["gt_py"], c["gt_pz"]], axis=1)
    q0 = np.array([c["gt_qw"][0], c["gt_qx"][0], c["gt_qy"][0], c["gt_qz"][0]])
    manager.reset(est.EstimateSample(0.0, q0, [c["gt_vx"][0], c["gt_vy"][0], c["gt_vz"][0]],
                                     truth[0]))
    for k in range(len(trot_log)):
        out = manager.update(c["t"][k], gyro[k], acc[k], q[k], dq[k], force[k], contact[k])
    assert out["initialised"] and out["start"] == "given" and out["P"].shape == (9, 9)
    assert out["contact"] == list(contact[-1])
    assert np.linalg.norm(out["x"].p - truth[-1]) < 0.005
    # The manager is the whole-log run's pipeline and filter, one sample at a time.
    whole = est.run(trot_log, settings)["invariant-ekf"]
    np.testing.assert_allclose(out["x"].p, whole["p"][-1], rtol=0, atol=1e-12)
    mid = 0.5 * (c["t"][-3] + c["t"][-2])
    x, age, interpolated = manager.state_at(mid)
    assert interpolated and age == 0.0 and x.t == pytest.approx(mid)
    with pytest.raises(ValueError, match="not after"):
        manager.update(c["t"][-1], gyro[-1], acc[-1], q[-1], dq[-1])
    with pytest.raises(ValueError, match="joint"):
        manager.update(c["t"][-1] + 1e-3, gyro[-1], acc[-1], q[-1][:6], dq[-1][:6])


def test_the_slip_check_sees_the_ice_push():
    """physics-ice-push: every foot slides once the push starts at 3.09 s (57.7.2)."""
    log = legkit.sim.simulate("physics-ice-push", duration=4.0)
    r = est.run(log, legkit.sim.settings_for("physics-ice-push"), estimators=["eskf"])["eskf"]
    slip = r["slip"]
    assert slip["reaction"] == "inflate" and slip["checked"].sum() > 4000
    assert slip["all_slipping"].any()
    assert r["t"][slip["all_slipping"]].min() > 3.09
    assert r["t"][slip["slipping"] > 0].min() > 3.09


def test_run_takes_a_gait_a_contact_model_and_a_start():
    log = legkit.sim.simulate("physics-trot", duration=3.0)
    settings = legkit.sim.settings_for("physics-trot")
    with pytest.raises(ValueError, match="gait"):
        est.run(log, settings, contact="gait-clock", estimators=["eskf"])
    gait = legkit.contact.planned_gait("physics-trot")
    clock = est.run(log, settings, contact="gait-clock", estimators=["eskf"], gait=gait)["eskf"]
    assert clock["contact_source"] == "gait-clock" and clock["healthy"]
    always = legkit.contact.LogisticModel([5.0, 0.0, 0.0, 0.0])  # p_c = sigma(5): every foot down
    mine = est.run(log, settings, contact="probabilistic", estimators=["eskf"], model=always)
    assert mine["eskf"]["contacts"][1000:].all()
    x0 = est.EstimateSample(0.0, [1, 0, 0, 0], [0, 0, 0], [10.0, -3.0, 0.3])
    moved = est.run(log, settings, estimators=["leg-odometry"], x0=x0)["leg-odometry"]
    np.testing.assert_allclose(moved["p"][0], [10.0, -3.0, 0.3], atol=1e-3)


def test_the_slip_check_flags_a_foot_that_slides():
    """Four feet hold a standing robot; then foot 2 reads 0.5 m/s of sliding: after three checks
    in a row (confirm_samples) it is slipping, the others are not (57.7)."""
    d = est.SlipDetector()
    assert d.threshold == pytest.approx(11.345, abs=1e-3)  # chi2_3(0.99)
    x = est.EstimateSample()
    P = np.diag([1e-4] * 3 + [1e-4] * 3 + [1e-4] * 3)

    def sample(k, slide):
        feet = [est.ContactMeasurement(i, p, 1e-6 * np.eye(3),
                                       v_body=np.array([slide if i == 2 else 0.0, 0, 0]))
                for i, p in enumerate(STANCE)]
        return d.check(k * 1e-3, 1e-3, np.zeros(3), G, feet, x, P)

    for k in range(5):
        r = sample(k, 0.0)
        assert not any(f["slipping"] or f["exceeds"] for f in r["feet"])
    flags = [[f["slipping"] for f in sample(k, 0.5)["feet"]] for k in range(5, 8)]
    assert flags == [[False] * 4, [False] * 4, [False, False, True, False]]
    assert sample(8, 0.5)["outlier"] == 2
