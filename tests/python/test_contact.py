"""legkit.contact: the detectors of 57.6 and the logistic contact model, from Python."""
import numpy as np
import pytest

import legkit

contact = legkit.contact


@pytest.fixture(scope="module")
def trot():
    log = legkit.sim.simulate("physics-trot", duration=4.0)
    truth = np.stack([log[f"gt_contact_{leg}"] for leg in legkit.model.LEGS], axis=1) > 0.5
    return log, truth


def test_the_chapters_detectors_are_there():
    names = contact.detector_names()
    for name in ("gait-clock", "grf-threshold", "schmitt", "momentum-observer", "probabilistic",
                 "kinematic"):
        assert name in names


@pytest.mark.parametrize("name,f1", [("schmitt", 0.98), ("grf-threshold", 0.97),
                                     ("gait-clock", 0.97), ("kinematic", 0.9)])
def test_detectors_on_a_physics_trot(trot, name, f1):
    log, truth = trot
    r = contact.detect(log, name, gait=contact.planned_gait("physics-trot"))
    assert r["contact"].shape == truth.shape and r["usable"].all()
    s = legkit.eval.score_contacts(r["t"][500:], r["contact"][500:], truth[500:])
    assert s["f1"] > f1, s


def test_the_logistic_model_is_a_sigmoid():
    model = contact.LogisticModel([0.5, 2.0, -1.0, 0.0], mean=[40.0, 0.1, 0.5],
                                  scale=[20.0, 0.2, 0.3])
    x = np.array([[60.0, 0.0, 0.2], [0.0, 0.5, 0.7]])
    z = 0.5 + ((x - [40.0, 0.1, 0.5]) / [20.0, 0.2, 0.3]) @ np.array([2.0, -1.0, 0.0])
    np.testing.assert_allclose(model.probability(x), 1 / (1 + np.exp(-z)), rtol=1e-14)
    assert model.uses_force and model.uses_foot_speed and not model.uses_phase


def test_training_on_physics_data_separates_stance_from_swing(trot):
    log, _ = trot
    x, y = contact.training_samples(log, contact.planned_gait("physics-trot"))
    assert x.shape == (4 * len(log), 3) and y.shape == (4 * len(log),) and y.dtype == bool
    model = contact.train_logistic(x, y)
    accuracy = np.mean((model.probability(x) > 0.5) == y)
    assert accuracy > 0.95, accuracy
    with pytest.raises(ValueError, match="class|label"):
        contact.train_logistic(x, np.ones_like(y))


def test_bad_arguments(trot):
    log, _ = trot
    with pytest.raises(ValueError, match="nope"):
        contact.detect(log, "nope")
    with pytest.raises(ValueError, match=r"w: expected shape \(4,\)"):
        contact.LogisticModel([1.0, 2.0])
