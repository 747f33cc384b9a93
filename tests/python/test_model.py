"""legkit.model: the quadruped's kinematics, checked from Python."""
import numpy as np
import pytest

import legkit

Q = np.array([0.1, 0.8, -1.6])


def test_foot_jacobian_is_the_derivative_of_the_foot_position():
    k = legkit.model.QuadrupedKinematics()
    for leg in range(4):
        J = k.foot_jacobian(leg, Q)
        h = 1e-6
        numeric = np.stack([(k.foot_position(leg, Q + h * e) - k.foot_position(leg, Q - h * e))
                            / (2 * h) for e in np.eye(3)], axis=1)
        np.testing.assert_allclose(J, numeric, atol=1e-8)


def test_inverse_kinematics_gives_the_angles_back():
    k = legkit.model.QuadrupedKinematics()
    for leg in range(4):
        p = k.foot_position(leg, Q)
        np.testing.assert_allclose(k.foot_position(leg, k.inverse_kinematics(leg, p)), p,
                                   atol=1e-12)


def test_legs_sit_where_their_names_say():
    k = legkit.model.QuadrupedKinematics()
    assert legkit.model.LEGS == ("FL", "FR", "RL", "RR")
    signs = {"FL": (1, 1), "FR": (1, -1), "RL": (-1, 1), "RR": (-1, -1)}
    for leg, name in enumerate(legkit.model.LEGS):
        p = k.foot_position(leg, [0.0, 0.8, -1.6])
        assert (np.sign(p[0]), np.sign(p[1])) == signs[name] and p[2] < -0.2


def test_a_longer_calf_reaches_further_down():
    g = legkit.model.QuadrupedGeometry()
    low = legkit.model.QuadrupedKinematics(g).foot_position(0, Q)[2]
    g.calf_length = g.calf_length + 0.05
    assert legkit.model.QuadrupedKinematics(g).foot_position(0, Q)[2] < low - 0.03


def test_bad_arguments():
    k = legkit.model.QuadrupedKinematics()
    with pytest.raises((ValueError, IndexError), match="leg"):
        k.foot_position(4, Q)
    with pytest.raises(ValueError, match=r"expected shape \(3,\)"):
        k.foot_position(0, Q[:2])
    with pytest.raises(TypeError, match="float64"):
        k.foot_position(0, Q.astype(np.float32))
