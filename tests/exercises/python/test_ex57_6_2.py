"""Exercise 57.6.2 in Python: the Newton step by hand and at the kit's optimum, the whole fit
against the kit's trainer (legkit.contact.train_logistic) on physics features, and the fitted
model run by the kit's LogisticContactDetector on another physics run, scored against the truth.
The checks of tests/exercises/ex57_6_2_test.cpp."""
import numpy as np
import pytest

import legkit

EXERCISE = "57.6.2"
FOLDER = "ex57_6_2_logistic_contact"


def physics_trot(seed):
    """8 s of the physics 2 Hz trot (1 s standing, then 0.5 m/s) from a seed."""
    return legkit.sim.simulate("physics-trot", duration=8.0, seed=seed)


@pytest.fixture(scope="module")
def gait():
    return legkit.contact.planned_gait("physics-trot")


@pytest.fixture(scope="module")
def training_set(gait):
    """Every foot and row of one run: features as the kit's detector computes them (base
    velocity and attitude from the truth), label = true contact."""
    return legkit.contact.training_samples(physics_trot(5762), gait)


@pytest.mark.hint(1)
def test_one_newton_step_by_hand(ex):
    # Two samples on the first feature, x = (1, +-1, 0, 0), labels 1 and 0, from w = 0: p = 1/2,
    # W = 1/4, g = (0, -1, 0, 0), H = diag(1/2, 1/2 + l2, l2, l2); with l2 = 1/2 the step is
    # w+ = (0, 1, 0, 0).
    X = np.array([[1.0, 1.0, 0.0, 0.0], [1.0, -1.0, 0.0, 0.0]])
    w1 = ex.newton_step(np.zeros(4), X, np.array([True, False]), 0.5)
    np.testing.assert_allclose(w1, [0.0, 1.0, 0.0, 0.0], rtol=0, atol=1e-12)
    # The bias is not penalised: four samples x = (1, 0, 0, 0), three positive, from w = 0:
    # sum (p - y) = 2 - 3 = -1 and sum W = 1, so w_0 moves by +1 whatever l2 (the log-odds log 3
    # is where the steps converge).
    ones = np.tile([1.0, 0.0, 0.0, 0.0], (4, 1))
    b1 = ex.newton_step(np.zeros(4), ones, np.array([True, True, True, False]), 10.0)
    np.testing.assert_allclose(b1, [1.0, 0.0, 0.0, 0.0], rtol=0, atol=1e-12)


@pytest.mark.hint(1)
def test_the_kits_optimum_is_a_fixed_point_of_your_step(ex):
    # Synthetic samples: force ~ 40 N in contact, ~ 10 N in swing, with overlap; speed and phase
    # likewise. The kit's trainer fits them; at its weights your step must not move.
    rng = np.random.default_rng(5762)
    labels = np.arange(400) % 3 != 0
    features = np.column_stack([
        np.where(labels, 40.0, 10.0) + 15.0 * rng.standard_normal(400),
        np.where(labels, 0.05, 0.6) + 0.3 * np.abs(rng.standard_normal(400)),
        np.where(labels, 0.3, 0.8) + 0.2 * rng.standard_normal(400),
    ])
    kit = legkit.contact.train_logistic(features, labels, l2=0.1)
    X = np.column_stack([np.ones(400), (features - kit.mean) / kit.scale])
    np.testing.assert_allclose(ex.newton_step(kit.w, X, labels, 0.1), kit.w, rtol=0, atol=1e-8)


@pytest.mark.hint(2)
def test_your_fit_is_the_kits_on_physics_features(ex, training_set):
    features, labels = training_set
    mine = ex.train_contact_probability(features, labels, 1e-3)
    kit = legkit.contact.train_logistic(features, labels, l2=1e-3)
    np.testing.assert_allclose(mine.mean, kit.mean, rtol=0, atol=1e-9 * np.linalg.norm(kit.mean))
    np.testing.assert_allclose(mine.scale, kit.scale, rtol=0,
                               atol=1e-9 * np.linalg.norm(kit.scale))
    np.testing.assert_allclose(mine.w, kit.w, rtol=0, atol=1e-6 * (1 + np.linalg.norm(kit.w)),
                               err_msg=f"{len(labels)} samples; the kit's w = {kit.w}")


@pytest.mark.hint(3)
def test_your_model_detects_contact_on_another_physics_run(ex, training_set, gait):
    model = ex.train_contact_probability(*training_set, 1e-3)
    # Another run (seed 5763), through the kit's detector with the planned gait, hysteresis 0.4
    # and a perfect base estimate as feedback, scored from t = 0.5 s on.
    log = physics_trot(5763)
    d = legkit.contact.detect(log, "probabilistic", gait=gait, model=model, hysteresis=0.4)
    scored = d["t"] >= 0.5
    truth = np.stack([log[f"gt_contact_{leg}"] for leg in legkit.model.LEGS], -1)[scored] != 0
    p = d["probability"][scored]
    assert d["usable"][scored].all(), d["problems"]
    s = legkit.eval.score_contacts(d["t"][scored], d["contact"][scored], truth)
    brier = np.mean((p - truth) ** 2)
    # Calibration at the ends: how many of the confident samples are truly in contact.
    low, high = truth[p < 0.1].mean(), truth[p >= 0.9].mean()
    scores = (f"F1 {s['f1']:.4f} (precision {s['precision']:.4f}, recall {s['recall']:.4f}); "
              f"Brier score {brier:.4f}; truly in contact: {low:.4f} of the samples with "
              f"p_c < 0.1, {high:.4f} of those with p_c >= 0.9")
    assert s["f1"] > 0.95, scores
    assert brier < 0.05, scores
    assert low < 0.05, scores
    assert high > 0.95, scores
