"""legkit.eval: the metrics against NumPy computations of the same definitions."""
import math

import numpy as np
import pytest

import legkit

est = legkit.estimators


@pytest.fixture(scope="module")
def run(trot_log):
    return est.run(trot_log, legkit.sim.settings_for("trot"), estimators=["eskf"])["eskf"]


def truth(log, key):
    return np.stack([log[f"gt_{key}{a}"] for a in "xyz"], axis=1)


def test_rmse_and_ate_against_numpy(trot_log, run):
    m = legkit.eval.compare(trot_log, run)
    p, v = truth(trot_log, "p"), truth(trot_log, "v")
    assert m["position_rmse"] == pytest.approx(
        math.sqrt(np.mean(np.sum((run["p"] - p) ** 2, axis=1))), rel=1e-12)
    assert m["velocity_rmse"] == pytest.approx(
        math.sqrt(np.mean(np.sum((run["v"] - v) ** 2, axis=1))), rel=1e-12)
    # ATE after the least-squares SE(3) alignment (Umeyama without scale), written out in NumPy.
    mu_e, mu_t = run["p"].mean(axis=0), p.mean(axis=0)
    U, _, Vt = np.linalg.svd((p - mu_t).T @ (run["p"] - mu_e))
    S = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    R = U @ S @ Vt
    aligned = (R @ (run["p"] - mu_e).T).T + mu_t
    ate = math.sqrt(np.mean(np.sum((aligned - p) ** 2, axis=1)))
    assert m["ate_se3_rmse"] == pytest.approx(ate, rel=1e-9)
    assert m["scored_rows"] == len(trot_log) and m["masked_rows"] == 0
    assert [r["distance"] for r in m["rpe"]] == [1.0, 5.0]


def test_compare_refuses_a_misaligned_estimate(trot_log, run):
    shorter = {k: run[k][:-1] for k in ("t", "q", "p", "v")}
    with pytest.raises(ValueError):
        legkit.eval.compare(trot_log, shorter)
    with pytest.raises(ValueError, match=r"estimate\['q'\]: expected shape"):
        legkit.eval.compare(trot_log, dict(run, q=run["q"][:, :3]))


def test_nees_of_a_known_error():
    x = est.EstimateSample(1.0, [1, 0, 0, 0], [0, 0, 0], [0, 0, 0])
    y = est.EstimateSample(1.0, [1, 0, 0, 0], [0, 0, 0], [0.3, -0.4, 0.0])
    P = np.diag([1e-2] * 6 + [0.25] * 3)
    assert legkit.eval.nees(x, y, P) == pytest.approx(0.25 / 0.25, rel=1e-12)
    with pytest.raises(ValueError, match=r"P: expected shape \(9, 9\)"):
        legkit.eval.nees(x, y, np.eye(6))


def test_chi_square():
    assert legkit.eval.chi_square_quantile(0.5, 2.0) == pytest.approx(2 * math.log(2), rel=1e-9)
    lower, upper = legkit.eval.anees_bounds(9, 1)
    # NEES of one run with 9 degrees of freedom: chi2inv(0.025, 9) and chi2inv(0.975, 9).
    assert lower == pytest.approx(2.7004, abs=1e-4)
    assert upper == pytest.approx(19.0228, abs=1e-4)


def test_contact_scores_of_a_delayed_detector():
    t = np.arange(4000) * 1e-3
    truth = ((t % 0.5) < 0.3)[:, None] & np.ones((1, 2), bool)
    detected = np.roll(truth, 5, axis=0)  # every event 5 ms late
    detected[:5] = truth[:5]
    s = legkit.eval.score_contacts(t, detected, truth)
    assert s["touchdown_delay_mean"] == pytest.approx(5.0, abs=1e-6)
    assert s["liftoff_delay_mean"] == pytest.approx(5.0, abs=1e-6)
    assert s["spurious_toggles"] == 0 and s["missed_touchdowns"] == 0
    assert s["f1"] == pytest.approx(1 - 5 * 2 * 8 / 4000 / 2 / (1 - 0.0), abs=0.02)
    with pytest.raises(ValueError, match="detected"):
        legkit.eval.score_contacts(t, detected[:, :1].astype(float), truth)
