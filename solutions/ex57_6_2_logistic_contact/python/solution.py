"""Reference solution of exercise 57.6.2 in Python: the logistic contact probability of 57.6
(method 5), p_c = sigma(w . (1, x_scaled)), fitted by Newton's method (iteratively reweighted
least squares) on the L2-penalised negative log-likelihood."""
import numpy as np

import legkit


def newton_step(w, X, y, l2):
    """w - H^-1 g with g = X^T (p - y) + l2 I' w and H = X^T W X + l2 I' (the bias is free)."""
    penalty = np.array([0.0, l2, l2, l2])  # the diagonal of l2 I'
    p = 1.0 / (1.0 + np.exp(-X @ w))
    g = X.T @ (p - np.asarray(y, dtype=float)) + penalty * w
    H = (X.T * (p * (1.0 - p))) @ X + np.diag(penalty)
    return w - np.linalg.solve(H, g)  # H is positive definite for l2 > 0 or a full-rank X


def train_contact_probability(features, labels, l2=1e-3):
    features = np.asarray(features, dtype=float)
    y = np.asarray(labels, dtype=bool)
    mean, scale = features.mean(axis=0), features.std(axis=0)  # std divides by n
    X = np.column_stack([np.ones(len(features)), (features - mean) / scale])
    w = np.array([np.log(y.sum() / (~y).sum()), 0.0, 0.0, 0.0])  # the labels' log-odds
    for _ in range(50):
        step = newton_step(w, X, y, l2) - w
        w = w + step
        if np.abs(step).max() < 1e-10:
            break
    return legkit.contact.LogisticModel(w, mean, scale)
