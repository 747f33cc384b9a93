"""legkit.lie against independent computations written here (Rodrigues, a series matrix
exponential, central differences, quadrature of the IMU ODE) and the identities of the C++ tests
in tests/lie/, plus the argument checks and the batched calls (equal to the single calls bit
for bit).
"""
import math
import pydoc

import numpy as np
import pytest

from legkit import lie
from legkit.lie import SE3, SE23, SEK3, SO3, imu

GRAVITY = np.array([0.0, 0.0, -9.81])


class Spec:
    """One group under test: its class and K (SO3 counts as K = 0)."""

    def __init__(self, cls, K):
        self.cls, self.K = cls, K
        self.dof, self.dim = 3 + 3 * K, 3 + K

    def __repr__(self):
        return f"{self.cls.__name__}(K={self.K})"

    def random(self, seed, scale=2.0):
        if self.cls is SO3:
            return SO3.Random(seed)
        if self.cls is SEK3:
            return SEK3.Random(self.K, seed, scale)
        return self.cls.Random(seed, scale)

    def tangent(self, rng, max_angle=3.0, scale=2.0):
        """A rotation of angle < max_angle first, then normal columns."""
        axis = rng.normal(size=3)
        phi = axis / np.linalg.norm(axis) * rng.uniform(0, max_angle)
        return np.concatenate([phi, scale * rng.normal(size=3 * self.K)])


SPECS = [Spec(SO3, 0), Spec(SE3, 1), Spec(SE23, 2), Spec(SEK3, 3), Spec(SEK3, 0)]
FIXED = SPECS[:3]


@pytest.fixture
def rng():
    return np.random.default_rng(2024)


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def rodrigues(phi):
    theta = np.linalg.norm(phi)
    if theta == 0:
        return np.eye(3)
    K = skew(phi / theta)
    return np.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K


def algebra(xi):
    """The (3+K)x(3+K) Lie algebra matrix of a tangent (phi, rho_1..rho_K), built here."""
    k = (len(xi) - 3) // 3
    M = np.zeros((3 + k, 3 + k))
    M[:3, :3] = skew(xi[:3])
    M[:3, 3:] = xi[3:].reshape(k, 3).T
    return M


def expm(A):
    """Matrix exponential by scaling and squaring of a 30-term Taylor series."""
    s = max(0, int(np.ceil(np.log2(max(np.abs(A).sum(axis=1).max(), 1e-300)))) + 1)
    B = A / 2.0**s
    term, E = np.eye(len(A)), np.eye(len(A))
    for n in range(1, 30):
        term = term @ B / n
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def central(f, n, h=1e-6):
    """Central differences of f: R^n -> R^m at 0, as an m x n matrix."""
    return np.column_stack([(f(h * e) - f(-h * e)) / (2 * h) for e in np.eye(n)])


def scale_of(X):
    return 1.0 + np.abs(X.matrix()).max()


# Exp, Log, hat, vee -------------------------------------------------------------------------


def test_so3_exp_is_rodrigues(rng):
    for theta in [0.0, 1e-300, 1e-12, 1e-6, 0.3, 1.0, 2.0, 3.0, math.pi - 1e-6, math.pi, 5.0]:
        u = rng.normal(size=3)
        phi = theta * u / np.linalg.norm(u)
        assert np.abs(SO3.Exp(phi).matrix() - rodrigues(phi)).max() <= 1e-15 * (1 + theta)


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_exp_is_the_matrix_exponential_of_hat(spec, rng):
    for _ in range(20):
        xi = spec.tangent(rng)
        assert np.array_equal(spec.cls.hat(xi), algebra(xi))
        assert np.array_equal(spec.cls.vee(algebra(xi)), xi)
        X = spec.cls.Exp(xi)
        assert np.abs(X.matrix() - expm(algebra(xi))).max() <= 1e-14 * (1 + np.linalg.norm(xi))


def test_so3_log_inverts_exp_near_0_and_pi(rng):
    for theta in [1e-300, 1e-150, 1e-12, 1e-8, 1e-4, 0.3, math.pi / 4, 1.7, 2.7, 3.0,
                  math.pi - 1e-6, math.pi - 1e-9]:
        for _ in range(20):
            u = rng.normal(size=3)
            phi = theta * u / np.linalg.norm(u)
            back = SO3.Exp(phi).Log()
            # The C++ bound (so3_test.cpp): relative, with a floor of a few ulp of pi.
            assert np.linalg.norm(back - phi) <= 1e-15 * theta + 1e-15 * (theta > 1e-3)
    # At pi, phi and -phi are the same rotation: Log lies in the closed ball of radius pi.
    for _ in range(20):
        u = rng.normal(size=3)
        X = SO3.Exp(math.pi * u / np.linalg.norm(u))
        assert np.linalg.norm(X.Log()) <= math.pi + 1e-15
        assert SO3.Exp(X.Log()).isApprox(X, 1e-14)


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_log_inverts_exp(spec, rng):
    for seed in range(20):
        xi = spec.tangent(rng)
        back = spec.cls.Exp(xi).Log()
        assert np.abs(back - xi).max() <= 1e-14 * (1 + np.abs(xi).max())
        X = spec.random(seed)
        assert spec.cls.Exp(X.Log()).isApprox(X, 1e-14)


# Group operations ---------------------------------------------------------------------------


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_compose_inverse_act_are_matrix_products(spec, rng):
    for seed in range(10):
        X, Y = spec.random(seed), spec.random(seed + 100)
        scale = scale_of(X) * scale_of(Y)
        XY = X.matrix() @ Y.matrix()
        assert np.abs((X * Y).matrix() - XY).max() <= 1e-15 * scale
        assert np.array_equal(X.compose(Y).matrix(), (X * Y).matrix())
        assert np.abs(X.inverse().matrix() - np.linalg.inv(X.matrix())).max() <= 1e-14 * scale
        assert (X * X.inverse()).isApprox(spec.cls.Exp(np.zeros(spec.dof)), 1e-14 * scale)
        x = rng.normal(size=3)
        R = X.matrix()[:3, :3]
        if spec.cls is SO3:
            assert np.abs(X.act(x) - R @ x).max() <= 1e-15 * (1 + np.abs(x).max())
            assert np.array_equal(X * x, X.act(x))
        for i in range(spec.K):
            c = X.matrix()[:3, 3 + i]
            assert np.abs(X.act(x, i) - (R @ x + c)).max() <= 1e-14 * scale
            assert np.array_equal(X.col(i), c)
    if spec.cls is SE3:
        assert np.array_equal(X * x, X.act(x)) and np.array_equal(X.translation(), X.col(0))


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_adjoint(spec, rng):
    for seed in range(10):
        X, Y = spec.random(seed), spec.random(seed + 100)
        xi, eta = spec.tangent(rng), spec.tangent(rng)
        left = X * spec.cls.Exp(xi) * X.inverse()
        assert left.isApprox(spec.cls.Exp(X.Adj() @ xi), 1e-13 * scale_of(X))
        scale = scale_of(X) * scale_of(Y)
        assert np.abs((X * Y).Adj() - X.Adj() @ Y.Adj()).max() <= 1e-14 * scale
        # ad is the commutator of the algebra: hat(ad(xi) eta) = [hat xi, hat eta].
        bracket = algebra(xi) @ algebra(eta) - algebra(eta) @ algebra(xi)
        assert np.abs(spec.cls.hat(spec.cls.ad(xi) @ eta) - bracket).max() <= 1e-14 * (
            1 + np.abs(bracket).max())


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_plus_minus_interpolate(spec, rng):
    for seed in range(10):
        X, Y = spec.random(seed), spec.random(seed + 100)
        tau = spec.tangent(rng, scale=1.0)
        scale = scale_of(X)
        assert np.array_equal(X.rplus(tau).matrix(), (X * spec.cls.Exp(tau)).matrix())
        assert np.array_equal(X.lplus(tau).matrix(), (spec.cls.Exp(tau) * X).matrix())
        assert np.abs(X.rplus(tau).rminus(X) - tau).max() <= 1e-13 * scale
        assert np.abs(X.lplus(tau).lminus(X) - tau).max() <= 1e-13 * scale**2
        assert X.rplus(Y.rminus(X)).isApprox(Y, 1e-13 * scale)
        assert X.interpolate(Y, 0.0).isApprox(X, 1e-15)
        assert X.interpolate(Y, 1.0).isApprox(Y, 1e-13 * scale)
        delta = Y.rminus(X)
        assert np.abs(X.interpolate(Y, 0.25).rminus(X) - 0.25 * delta).max() <= 1e-13 * scale


# Jacobians ----------------------------------------------------------------------------------


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_jr_jl_against_finite_differences(spec, rng):
    G = spec.cls
    for _ in range(5):
        xi = spec.tangent(rng)
        X = G.Exp(xi)
        Jr = central(lambda d: (X.inverse() * G.Exp(xi + d)).Log(), spec.dof)
        Jl = central(lambda d: (G.Exp(xi + d) * X.inverse()).Log(), spec.dof)
        assert np.abs(G.Jr(xi) - Jr).max() <= 1e-8 * scale_of(X)
        assert np.abs(G.Jl(xi) - Jl).max() <= 1e-8 * scale_of(X)


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_jacobian_identities(spec, rng):
    G, eye = spec.cls, np.eye(spec.dof)
    for _ in range(10):
        xi = spec.tangent(rng)
        assert np.abs(G.JrInv(xi) @ G.Jr(xi) - eye).max() <= 1e-13 * (1 + np.abs(xi).max())
        assert np.abs(G.JlInv(xi) @ G.Jl(xi) - eye).max() <= 1e-13 * (1 + np.abs(xi).max())
        assert np.array_equal(G.Jl(xi), G.Jr(-xi))
        assert np.array_equal(G.JlInv(xi), G.JrInv(-xi))
        # Jl = Ad_{Exp(xi)} Jr.
        X = G.Exp(xi)
        assert np.abs(G.Jl(xi) - X.Adj() @ G.Jr(xi)).max() <= 1e-13 * scale_of(X)


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_optional_jacobian_outputs(spec, rng):
    G = spec.cls
    xi = spec.tangent(rng)
    X, Y = spec.random(1), spec.random(2)
    tol = 1e-8 * scale_of(X) * scale_of(Y)

    E, J = G.Exp(xi, jacobians=True)
    assert np.array_equal(E.matrix(), G.Exp(xi).matrix()) and np.array_equal(J, G.Jr(xi))

    phi, J = X.Log(jacobians=True)
    assert np.array_equal(phi, X.Log()) and np.array_equal(J, G.JrInv(phi))
    assert np.abs(J - central(lambda d: X.rplus(d).Log(), spec.dof)).max() <= tol

    Xi, J = X.inverse(jacobians=True)
    assert np.array_equal(Xi.matrix(), X.inverse().matrix()) and np.array_equal(J, -X.Adj())
    assert np.abs(J - central(lambda d: X.rplus(d).inverse().rminus(Xi), spec.dof)).max() <= tol

    XY, JX, JY = X.compose(Y, jacobians=True)
    assert np.array_equal(XY.matrix(), (X * Y).matrix())
    assert np.abs(JX - central(lambda d: (X.rplus(d) * Y).rminus(XY), spec.dof)).max() <= tol
    assert np.abs(JY - central(lambda d: (X * Y.rplus(d)).rminus(XY), spec.dof)).max() <= tol

    x = rng.normal(size=3)
    for column in [()] if spec.cls is SO3 else [(i,) for i in range(spec.K)]:
        y, JX, Jx = X.act(x, *column, jacobians=True)
        assert np.array_equal(y, X.act(x, *column))
        assert np.abs(JX - central(lambda d: X.rplus(d).act(x, *column), spec.dof)).max() <= tol
        assert np.abs(Jx - central(lambda d: X.act(x + d, *column), 3)).max() <= tol


# SO3 specifics, fromMatrix ------------------------------------------------------------------


def test_so3_quaternion(rng):
    for _ in range(20):
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        theta = rng.uniform(0, math.pi)
        X = SO3.Exp(theta * u)
        q = X.quaternion()
        expected = np.concatenate([[math.cos(theta / 2)], math.sin(theta / 2) * u])
        assert min(np.abs(q - expected).max(), np.abs(q + expected).max()) <= 1e-15
        assert SO3.fromQuaternion(q).isApprox(X, 1e-14)
        assert SO3.fromQuaternion(3 * q).isApprox(X, 1e-14)  # normalised
    with pytest.raises(ValueError, match="zero quaternion"):
        SO3.fromQuaternion(np.zeros(4))


@pytest.mark.parametrize("spec", SPECS, ids=repr)
def test_from_matrix_checks_like_the_cpp(spec, rng):
    G = spec.cls
    M = G.Exp(spec.tangent(rng)).matrix()
    assert np.array_equal(G.fromMatrix(M).matrix(), M)
    bad = M.copy()
    bad[:3, :3] *= 1.01
    with pytest.raises(lie.NotInGroup, match=r"fromMatrix: matrix is not orthonormal \(max"):
        G.fromMatrix(bad)
    bad = M.copy()
    bad[:3, :3] = M[:3, :3] @ np.diag([1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match="determinant is -1 \\(a reflection"):
        G.fromMatrix(bad)
    bad = M.copy()
    bad[0, 1] = np.nan
    with pytest.raises(lie.NotInGroup, match="matrix has a NaN or inf entry"):
        G.fromMatrix(bad)
    if spec.K > 0:
        bad = M.copy()
        bad[-1, 0] = 1e-6
        with pytest.raises(lie.NotInGroup, match=r"the last \d rows must be \[0 \| I\]"):
            G.fromMatrix(bad)
        assert G.fromMatrix(bad, tol=1e-5).isApprox(G.fromMatrix(M), 0.0)
    assert issubclass(lie.NotInGroup, ValueError)


def test_sek3_from_matrix_names_a_wrong_size():
    with pytest.raises(lie.NotInGroup, match="expected a square matrix of size 3\\+K.* got 4x5"):
        SEK3.fromMatrix(np.eye(4, 5))
    with pytest.raises(ValueError, match=r"M: expected shape \(n, m\) with n <= 11, m <= 11"):
        SEK3.fromMatrix(np.eye(12))
    with pytest.raises(ValueError, match="M: expected a square matrix of size 3\\+K, got 4x5"):
        SEK3.vee(np.eye(4, 5))
    with pytest.raises(ValueError, match=r"M: expected shape \(5, 5\), got \(4, 4\)"):
        SE23.fromMatrix(np.eye(4))


# SEK3 against SE3 and SE23, columns ----------------------------------------------------------


@pytest.mark.parametrize("fixed", [SE3, SE23], ids=["SE3", "SE23"])
def test_sek3_gives_the_bits_of_the_fixed_groups(fixed, rng):
    K = fixed.K
    for seed in range(5):
        X, Xd = fixed.Random(seed, 3.0), SEK3.Random(K, seed, 3.0)
        Y, Yd = fixed.Random(seed + 9), SEK3.Random(K, seed + 9)
        assert np.array_equal(X.matrix(), Xd.matrix())
        xi = Spec(fixed, K).tangent(rng)
        x = rng.normal(size=3)
        for f in ["Exp", "Jr", "Jl", "JrInv", "JlInv", "hat", "ad"]:
            a, b = getattr(fixed, f)(xi), getattr(SEK3, f)(xi)
            if f == "Exp":
                a, b = a.matrix(), b.matrix()
            assert np.array_equal(a, b), f
        for a, b in [(X.Log(), Xd.Log()), (X.Adj(), Xd.Adj()), (X.act(x, K - 1), Xd.act(x, K - 1)),
                     ((X * Y).matrix(), (Xd * Yd).matrix()),
                     (X.inverse().matrix(), Xd.inverse().matrix()),
                     (X.rplus(xi).matrix(), Xd.rplus(xi).matrix()),
                     (X.interpolate(Y, 0.3).matrix(), Xd.interpolate(Yd, 0.3).matrix()),
                     (fixed.Exp_batch(xi[None])[0], SEK3.Exp(xi).matrix())]:
            assert np.array_equal(a, b)
    if fixed is SE23:
        w, a = np.array([0.3, -0.2, 0.9]), np.array([0.1, 0.4, 9.5])
        P, Pd = imu.propagate(X, w, a, GRAVITY, 0.01), imu.propagate(Xd, w, a, GRAVITY, 0.01)
        assert type(P) is SE23 and type(Pd) is SEK3
        assert np.array_equal(P.matrix(), Pd.matrix())
        assert np.array_equal(imu.phiWithBias(P, w, a, GRAVITY, 0.01),
                              imu.phiWithBias(Pd, w, a, GRAVITY, 0.01))


def test_sek3_columns():
    R = SO3.Exp([0.1, 0.2, 0.3])
    C = np.arange(9.0).reshape(3, 3)
    X = SEK3(R, C)
    assert X.numCols() == 3 and X.dof() == 12 and SEK3.MaxK == 8
    assert np.array_equal(X.columns(), C) and np.array_equal(X.R(), R.matrix())
    assert X.rotation().isApprox(R, 0.0)
    X.appendColumn([9.0, 10.0, 11.0])
    assert X.numCols() == 4 and np.array_equal(X.col(3), [9.0, 10.0, 11.0])
    X.removeColumn(0)
    assert np.array_equal(X.columns(), np.column_stack([C[:, 1], C[:, 2], [9.0, 10.0, 11.0]]))
    assert np.array_equal(SEK3(2).matrix(), np.eye(5))
    assert np.array_equal(SEK3.Identity(0).matrix(), np.eye(3))
    assert np.array_equal(SE3(R, [1.0, 2.0, 3.0]).translation(), [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="SEK3: 9 columns requested, this group holds at most 8"):
        SEK3(9)
    with pytest.raises(ValueError, match="K = -1: SEK3 holds 0 to 8 columns"):
        SEK3.Random(-1, 0)
    with pytest.raises(ValueError, match="K = 9: SEK3 holds 0 to 8 columns"):
        SEK3.Random(9, 0)
    with pytest.raises(ValueError, match="SEK3::operator\\*: operands have 2 and 3 columns"):
        SEK3(2) * SEK3(3)
    with pytest.raises(ValueError, match="operands have 2 and 1 columns"):
        SEK3(2).rplus(np.zeros(6))
    with pytest.raises(ValueError, match="SEK3::Exp: tangent vector of size 5 is not 3 \\+ 3K"):
        SEK3.Exp(np.zeros(5))
    with pytest.raises(IndexError, match="SEK3::act: no such column"):
        SEK3(2).act([1.0, 2.0, 3.0], 2)
    with pytest.raises(IndexError, match="no such column: 3"):
        X.col(3)
    with pytest.raises(IndexError, match="SEK3::removeColumn: no such column"):
        X.removeColumn(5)
    with pytest.raises(ValueError, match=r"C: expected shape \(3, 2\), got \(3, 3\)"):
        SE23(R, C)


# Batched calls ------------------------------------------------------------------------------


@pytest.mark.parametrize("spec", FIXED, ids=repr)
def test_batched_equals_single_calls_bit_for_bit(spec, rng):
    G = spec.cls
    xi = np.array([spec.tangent(rng, max_angle=math.pi) for _ in range(300)])
    xi[0] = 0.0
    xi[1, :3] = [1e-9, 0.0, 0.0]
    xi[2, :3] = [0.0, 0.0, math.pi]
    M = G.Exp_batch(xi)
    assert M.shape == (300, spec.dim, spec.dim) and M.flags.c_contiguous
    assert np.array_equal(M, np.array([G.Exp(x).matrix() for x in xi]))
    logs = G.Log_batch(M)
    assert logs.shape == (300, spec.dof)
    assert np.array_equal(logs, np.array([G.fromMatrix(m).Log() for m in M]))
    # Non-contiguous input (one copy) and lists give the same bits; N = 0 is fine.
    wide = np.zeros((300, 2 * spec.dof))
    wide[:, ::2] = xi
    assert np.array_equal(G.Exp_batch(wide[:, ::2]), M)
    assert np.array_equal(G.Exp_batch(xi[:5].tolist()), M[:5])
    assert np.array_equal(G.Log_batch(np.asfortranarray(M)), logs)
    assert G.Exp_batch(np.zeros((0, spec.dof))).shape == (0, spec.dim, spec.dim)
    assert G.Log_batch(np.zeros((0, spec.dim, spec.dim))).shape == (0, spec.dof)


def test_batched_calls_reject_bad_input():
    with pytest.raises(ValueError, match=r"phi: expected shape \(N, 3\), got \(5, 4\)"):
        SO3.Exp_batch(np.zeros((5, 4)))
    with pytest.raises(ValueError, match=r"xi: expected shape \(N, 9\), got \(9,\)"):
        SE23.Exp_batch(np.zeros(9))
    with pytest.raises(ValueError, match=r"M: expected shape \(N, 4, 4\), got \(2, 3, 3\)"):
        SE3.Log_batch(np.zeros((2, 3, 3)))
    with pytest.raises(TypeError, match="phi: expected a float64 array, got dtype float32"):
        SO3.Exp_batch(np.zeros((5, 3), np.float32))
    phi = np.zeros((5, 3))
    phi[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"phi\[3\] is not finite"):
        SO3.Exp_batch(phi)
    M = SO3.Exp_batch(np.ones((4, 3)))
    M[2] *= 1.1
    with pytest.raises(lie.NotInGroup, match=r"M\[2\]: SO3::fromMatrix: matrix is not orthonormal"):
        SO3.Log_batch(M)
    M[2, 0, 0] = np.inf
    with pytest.raises(lie.NotInGroup, match=r"M\[2\]: SO3::fromMatrix: matrix has a NaN or inf"):
        SO3.Log_batch(M)


# The IMU model ------------------------------------------------------------------------------


def error_dynamics(K, g):
    """A of imu_dynamics.hpp on (phi, v, p, d_1..): [[0,0,0],[[g]x,0,0],[0,I,0]]."""
    A = np.zeros((3 + 3 * K, 3 + 3 * K))
    A[3:6, 0:3] = skew(g)
    A[6:9, 3:6] = np.eye(3)
    return A


def test_imu_phi_is_the_closed_form_and_the_exponential():
    for K in range(2, 9):
        for dt in [1e-3, 0.1, 1.0, 5.0]:
            A = error_dynamics(K, GRAVITY)
            F = imu.phi(K, GRAVITY, dt)
            expected = np.eye(3 + 3 * K) + A * dt + A @ A * dt**2 / 2  # A^3 = 0
            assert np.abs(F - expected).max() <= 1e-15 * np.abs(expected).max()
            assert np.abs(F - expm(A * dt)).max() <= 1e-14 * np.abs(expected).max()


@pytest.mark.parametrize("group", [SE23, SEK3], ids=["SE23", "SEK3(K=4)"])
def test_imu_propagate_solves_the_ode(group):
    """Against the ODE's solution written here: R(t) = R0 Exp(w t) (Rodrigues), and v, p from
    Gauss-Legendre quadrature of R(s) a + g (exact to rounding for these smooth integrands)."""
    nodes, weights = np.polynomial.legendre.leggauss(30)
    cases = [([0.8, -0.5, 1.2], [1.0, -2.0, 9.5], 1.0), ([-3.0, 4.0, 4.0], [0.5, 0.5, 12.0], 0.5),
             ([1e-4, 2e-4, -1e-4], [0.1, 0.0, 9.8], 0.02), ([0.0, 0.0, 0.0], [0.0, 1.0, 9.81], 0.3)]
    for seed, (w, a, dt) in enumerate(cases):
        w, a = np.array(w), np.array(a)
        X = SE23.Random(seed, 2.0) if group is SE23 else SEK3.Random(4, seed, 2.0)
        Y = imu.propagate(X, w, a, GRAVITY, dt)
        R0, v0, p0 = X.R(), X.col(0), X.col(1)
        s = dt * (nodes + 1) / 2
        Ra = np.array([R0 @ rodrigues(w * si) @ a for si in s])  # R(s) a at the nodes
        dv = (weights * dt / 2) @ Ra
        dp = (weights * dt / 2 * (dt - s)) @ Ra  # int_0^dt (dt - s) R(s) a ds
        assert np.abs(Y.R() - R0 @ rodrigues(w * dt)).max() <= 1e-14
        v, p = v0 + dv + GRAVITY * dt, p0 + v0 * dt + dp + GRAVITY * dt**2 / 2
        assert np.abs(Y.col(0) - v).max() <= 1e-13 * (1 + np.abs(v).max())
        assert np.abs(Y.col(1) - p).max() <= 1e-13 * (1 + np.abs(p).max())
        for i in range(2, X.numCols()):
            assert np.array_equal(Y.col(i), X.col(i))  # contacts stay


def test_imu_right_invariant_error_is_log_linear():
    """The C++ test's claim over 200 steps: Log(Xhat_N X_N^-1) = Phi^N xi_0, however large xi_0."""
    K, dt = 6, 0.005
    X = SEK3.Random(K, 2026, 3.0)
    xi0 = np.array([1.1, -0.9, 1.2, 1.5, -2.0, 0.7, 4.0, 3.0, -2.5, 0.3, -0.2, 0.1, -0.5, 0.4, 0.2,
                    1.0, 0.0, -0.3, 0.2, 0.6, -0.7])
    Xhat = SEK3.Exp(xi0) * X
    F = imu.phi(K, GRAVITY, dt)
    xi = (Xhat * X.inverse()).Log()
    for step in range(200):
        t = step * dt
        w = np.array([1.5 * math.sin(0.7 * t), 0.8 * math.cos(1.3 * t), 0.4 + math.sin(2.1 * t)])
        a = np.array([2 * math.sin(t), -1.5 * math.cos(0.5 * t), 9.81 + 3 * math.sin(1.7 * t)])
        X, Xhat = imu.propagate(X, w, a, GRAVITY, dt), imu.propagate(Xhat, w, a, GRAVITY, dt)
        xi = F @ xi
    assert np.linalg.norm(xi - xi0) > 1  # the error changed
    assert np.abs((Xhat * X.inverse()).Log() - xi).max() <= 1e-10 * np.abs(xi).max()


@pytest.mark.parametrize("K", [2, 5])
def test_imu_phi_with_bias_against_finite_differences(K):
    X = SEK3.Random(K, 77, 3.0)
    w, a, dt = np.array([3.0, -2.0, 1.5]), np.array([2.0, -1.0, 9.0]), 0.05
    Xhat = imu.propagate(X, w, a, GRAVITY, dt)
    F = imu.phiWithBias(Xhat, w, a, GRAVITY, dt)
    n = 3 + 3 * K
    assert F.shape == (n + 6, n + 6)
    assert np.array_equal(F[:n, :n], imu.phi(K, GRAVITY, dt))
    assert np.array_equal(F[n:], np.hstack([np.zeros((6, n)), np.eye(6)]))
    # The truth uses the input plus the bias error zeta (gyro, accel), the estimate the input.
    B = central(lambda z: (Xhat * imu.propagate(X, w + z[:3], a + z[3:], GRAVITY, dt).inverse())
                .Log(), 6)
    assert np.abs(F[:n, n:] - B).max() <= 1e-7 * np.abs(B).max()


def test_imu_errors():
    with pytest.raises(ValueError, match="lie::imu::propagate: needs columns v and p"):
        imu.propagate(SEK3(1), [0.0, 0.0, 0.0], [0.0, 0.0, 9.81], GRAVITY, 0.01)
    with pytest.raises(ValueError, match="lie::imu::phi: needs columns v and p .* got 1 column"):
        imu.phi(1, GRAVITY, 0.01)
    with pytest.raises(ValueError, match="K = 9: SEK3 holds 0 to 8 columns"):
        imu.phi(9, GRAVITY, 0.01)
    with pytest.raises(ValueError, match="dt is not finite"):
        imu.propagate(SE23(), [0.0, 0.0, 0.0], [0.0, 0.0, 9.81], GRAVITY, math.nan)
    with pytest.raises(ValueError, match=r"g: expected shape \(3,\), got \(2,\)"):
        imu.phi(2, [0.0, -9.81], 0.01)
    with pytest.raises(TypeError, match="incompatible function arguments"):
        imu.propagate(SE3(), [0.0, 0.0, 0.0], [0.0, 0.0, 9.81], GRAVITY, 0.01)


# Argument checks ----------------------------------------------------------------------------


def test_arguments_are_float64_of_the_right_shape_and_finite():
    phi = np.array([0.1, -0.2, 0.3])
    with pytest.raises(ValueError, match=r"phi: expected shape \(3,\), got \(4,\)"):
        SO3.Exp(np.zeros(4))
    with pytest.raises(ValueError, match=r"phi: expected shape \(3,\), got \(3, 1\)"):
        SO3.Exp(np.zeros((3, 1)))
    with pytest.raises(ValueError, match=r"xi: expected shape \(6,\), got \(9,\)"):
        SE3.Exp(np.zeros(9))
    with pytest.raises(ValueError, match=r"xi: expected shape \(n,\) with n <= 27, got \(30,\)"):
        SEK3.Exp(np.zeros(30))
    for dtype in [np.float32, np.int64, np.complex128, np.bool_]:
        with pytest.raises(TypeError, match="phi: expected a float64 array, got dtype"):
            SO3.Exp(phi.astype(dtype))
    with pytest.raises(TypeError, match="phi: expected a float64 array or numbers, got str"):
        SO3.Exp("abc")
    for bad in [np.nan, np.inf, -np.inf]:
        with pytest.raises(ValueError, match="^phi is not finite$"):
            SO3.Exp([0.0, bad, 0.0])
        with pytest.raises(ValueError, match="^x is not finite$"):
            SO3().act([bad, 0.0, 0.0])
        with pytest.raises(ValueError, match="^tau is not finite$"):
            SE23().rplus(np.full(9, bad))
    with pytest.raises(ValueError, match="^t is not finite$"):
        SO3().interpolate(SO3(), math.nan)
    # Lists convert; any strides are fine (small arguments are copied anyway).
    expected = SO3.Exp(phi).matrix()
    assert np.array_equal(SO3.Exp(phi.tolist()).matrix(), expected)
    assert np.array_equal(SO3.Exp((0.1, -0.2, 0.3)).matrix(), expected)
    strided = np.zeros(6)
    strided[::2] = phi
    assert np.array_equal(SO3.Exp(strided[::2]).matrix(), expected)
    assert np.array_equal(SO3.fromMatrix(np.asfortranarray(expected)).matrix(), expected)


def test_results_are_new_arrays():
    X = SE23.Random(3)
    M = X.matrix()
    M[0, 0] = 7.0
    assert X.matrix()[0, 0] != 7.0
    assert X.Log().flags.c_contiguous and X.Log().flags.writeable and X.Adj().flags.c_contiguous
    phi = np.array([0.1, 0.2, 0.3])
    assert not np.shares_memory(SO3.vee(SO3.hat(phi)), phi)


def test_docstrings_carry_the_cpp_comments():
    assert "Rodrigues: Exp(phi) = I + G_1 [phi]x + G_2 [phi]x^2" in pydoc.render_doc(SO3.Exp)
    assert "rotation vector in rad" in SO3.Exp.__doc__
    assert "Exp(phi + d) = Exp(phi) Exp(Jr(phi) d)" in SO3.Exp.__doc__
    assert "phi: numpy.ndarray[numpy.float64]" in SO3.Exp.__doc__
    assert "rotation FIRST" in SE23.Exp.__doc__
    assert "Ad_X = [[R, 0], [[c_i]x R, R]]" in SE3.Adj.__doc__
    for text in ["dv/dt = R a + g", "w [rad/s]", "a [m/s^2]", "gravity g [m/s^2]", "dt [s]"]:
        assert text in imu.propagate.__doc__, text
    assert "I + A dt + A^2 dt^2/2" in imu.phi.__doc__
    assert "gyro first" in imu.phiWithBias.__doc__
    for text in ["float64", "TypeError", "C-contiguous", "copy", "GIL"]:
        assert text in lie.__doc__, text


def test_repr():
    assert repr(SO3()) == "SO3([[1, 0, 0], [0, 1, 0], [0, 0, 1]])"
    assert repr(SEK3(1)) == "SEK3([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])"
