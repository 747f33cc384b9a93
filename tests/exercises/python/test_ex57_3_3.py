"""Exercise 57.3.3 in Python: leg odometry over a simulated log (the kit's simulator writes it,
its reader reads it back), compared with the log's ground truth. The checks of
tests/exercises/ex57_3_3_test.cpp, plus one stance foot by hand and every missing column group."""
import numpy as np
import pytest

import legkit

EXERCISE = "57.3.3"
FOLDER = "ex57_3_3_log_leg_odometry"


def simulated(scenario, duration, noiseless):
    return legkit.sim.simulate(scenario, duration=duration, seed=5733, noiseless=noiseless)


@pytest.fixture(scope="module")
def kin():
    return legkit.model.QuadrupedKinematics()


@pytest.mark.hint(1)
def test_one_stance_foot_by_hand(ex, kin):
    # FR alone in contact, the base yawed by 90 deg and turning: joint rates chosen so that the
    # foot stands still for a base velocity v. The other legs' rates are nonsense: not in contact.
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    w = np.array([0.1, -0.2, 0.3])
    v = np.array([0.5, -0.1, 0.05])
    q = np.tile([0.1, 0.8, -1.5], 4)
    r, J = kin.foot_position(1, q[3:6]), kin.foot_jacobian(1, q[3:6])
    dq = np.full(12, 99.0)
    dq[3:6] = np.linalg.solve(J, -R.T @ v - np.cross(w, r))  # 0 = v + R (w x r + J dq)
    got = ex.row_velocity(R, w, q, dq, np.array([False, True, False, False]), kin)
    assert got is not None
    np.testing.assert_allclose(got, v, atol=1e-12)


@pytest.mark.hint(1)
def test_noiseless_trot_log_equals_the_truth(ex, kin, tmp_path):
    path = tmp_path / "trot.csv"
    legkit.io.write_log(str(path), simulated("trot", 3.0, noiseless=True))
    c = ex.compare_log_file(str(path), kin)
    assert (c.rows_used, c.rows_without_contact) == (3000, 0)
    assert c.rmse < 1e-6, f"rmse {c.rmse} m/s"
    assert c.max_error < 1e-5, f"largest error {c.max_error} m/s"


@pytest.mark.hint(2)
def test_noisy_turning_log_errs_at_the_gyro_noise_level(ex, kin):
    # Per 1 kHz sample the Go2 gyro's white noise is 0.004 rad/s/sqrt(Hz) * sqrt(1000 Hz) = 0.13
    # rad/s per axis; through w x r with |r| ~ 0.35 m that is a few cm/s, common to every foot.
    c = ex.compare_with_truth(simulated("turn", 3.0, noiseless=False), kin)
    assert c.rows_used == 3000
    assert 0.01 < c.rmse < 0.1, f"rmse {c.rmse} m/s"


@pytest.mark.hint(3)
def test_flight_rows_give_no_velocity_and_are_counted(ex, kin):
    log = simulated("bound", 3.0, noiseless=True)
    contact = np.stack([log[f"contact_{leg}"] for leg in legkit.model.LEGS], -1) != 0
    flight = np.flatnonzero(~contact.any(axis=1))
    assert len(flight) > 0
    q = np.stack([log[f"q_{leg}_{j}"] for leg in legkit.model.LEGS for j in range(3)], -1)
    dq = np.stack([log[f"dq_{leg}_{j}"] for leg in legkit.model.LEGS for j in range(3)], -1)
    gyro = np.stack([log[f"gyro_{a}"] for a in "xyz"], -1)
    for k in flight:
        assert ex.row_velocity(np.eye(3), gyro[k], q[k], dq[k], contact[k], kin) is None
    c = ex.compare_with_truth(log, kin)
    assert c.rows_without_contact == len(flight)
    assert c.rows_used + len(flight) == len(log)
    assert c.rmse < 1e-6, f"rmse {c.rmse} m/s"


@pytest.mark.hint(4)
@pytest.mark.parametrize("missing", ["gt_", "gt_v", "contact_"])
def test_a_log_without_what_it_needs_is_rejected(ex, kin, missing):
    # No truth at all, a pose-only truth (no gt_v*), no contact flags.
    columns = simulated("stand", 0.1, noiseless=True).to_dict()
    log = legkit.io.Log.from_columns(
        {name: c for name, c in columns.items() if not name.startswith(missing)})
    with pytest.raises(ValueError):
        ex.compare_with_truth(log, kin)
