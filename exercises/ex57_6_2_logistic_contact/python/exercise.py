"""Exercise 57.6.2 in Python: the logistic contact probability p_c = sigma(w . x) of section 57.6
(method 5), trained by Newton's method in NumPy on the kit's physics data.

Replace each `raise NotImplementedError(...)` with NumPy code. The samples come from the kit's
C++ (legkit.contact.training_samples of a legkit.sim.simulate("physics-trot") log), your model
goes back into it (legkit.contact.LogisticModel(w, mean, scale), run by the kit's detector,
legkit.contact.detect), and the tests hold your fit against the kit's trainer
(legkit.contact.train_logistic). The task, the tests and the hints: ../README.md, "Python
variant". Run the tests: tools/exercise 57.6.2 --python
"""
import numpy as np  # you will need it

import legkit  # legkit.contact.LogisticModel

STUB = "exercises/ex57_6_2_logistic_contact/python/exercise.py"


def newton_step(w, X, y, l2):
    """One Newton step on the L2-penalised negative log-likelihood of the labels,
        L(w) = -sum_n [y_n log p_n + (1 - y_n) log(1 - p_n)] + l2/2 (w_1^2 + w_2^2 + w_3^2),
        p_n = sigma(w . x_n),   sigma(z) = 1 / (1 + e^-z),
    for samples x_n = (1, scaled F_n, scaled |v_foot|, scaled phi) (the bias w_0 is not
    penalised):
        w+ = w - (X^T W X + l2 I')^-1 (X^T (p - y) + l2 I' w),   W = diag(p_n (1 - p_n)),
    I' = diag(0, 1, 1, 1).
      w   (4,) the weights (b, w_F, w_v, w_phi)
      X   (N, 4) the samples x_n, one per row (N >= 1)
      y   (N,) bool labels, True: in contact
      l2  the penalty's weight, >= 0
    Returns w+, (4,).
    """
    raise NotImplementedError(f"newton_step: not implemented yet ({STUB})")


def train_contact_probability(features, labels, l2=1e-3):
    """The whole fit, all three features used: per feature its mean and standard deviation over
    the samples (divide by n, not n - 1); every sample scaled, x_n = (1, (F - mean_F) / scale_F,
    ...); from w = (log(positives / negatives), 0, 0, 0), Newton steps until the largest
    component of a step is below 1e-10 (at most 50 steps).
      features  (N, 3) one sample per row: force F_n [N], foot speed |v_foot| [m/s], planned
                gait phase phi in [0, 1)
      labels    (N,) bool, the true contact
    Returns legkit.contact.LogisticModel(w, mean, scale) (w (4,), mean and scale (3,)).
    """
    raise NotImplementedError(f"train_contact_probability: not implemented yet ({STUB})")
