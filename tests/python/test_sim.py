"""legkit.sim: the scenarios to a log in memory."""
import numpy as np
import pytest

import legkit


def test_scenario_names():
    names = legkit.sim.scenario_names()
    assert names[:3] == ["stand", "walk", "trot"]
    assert "physics-trot" in names and "physics-real" in names


def test_seeded_and_shaped():
    a = legkit.sim.simulate("turn", duration=1.0, seed=7)
    b = legkit.sim.simulate("turn", duration=1.0, seed=7)
    c = legkit.sim.simulate("turn", duration=1.0, seed=8)
    assert len(a) == 1000 and a.layout.joints and a.layout.ground_truth
    assert np.array_equal(a["gyro_z"], b["gyro_z"])
    assert not np.array_equal(a["gyro_z"], c["gyro_z"])
    exact = legkit.sim.simulate("stand", duration=0.5, noiseless=True)
    assert np.all(exact["gyro_x"] == 0.0)  # standing still, before the sway starts
    half = legkit.sim.simulate("trot", duration=1.0, rate=500.0, ground_truth=False)
    assert len(half) == 500 and not half.layout.ground_truth


def test_physics_logs_carry_the_true_contact():
    log = legkit.sim.simulate("physics-stand", duration=0.5)
    assert len(log) == 500 and log.layout.contact_truth and log.layout.force
    assert np.all(log["gt_contact_FL"][-100:] == 1.0)


def test_settings_for_a_scenario():
    analytic = legkit.sim.settings_for("trot")
    assert analytic.contact == "truth"
    assert legkit.sim.settings_for("physics-trot").contact != "truth"


def test_bad_options_are_errors():
    with pytest.raises(ValueError, match="unknown scenario 'nope'.*trot"):
        legkit.sim.simulate("nope")
    with pytest.raises(ValueError, match="duration"):
        legkit.sim.simulate("trot", duration=-1.0)
    with pytest.raises(ValueError, match="duration"):
        legkit.sim.simulate("physics-trot", duration=float("nan"))
