"""Reference solution of exercise 57.3.3 in Python, on the kit's kinematics (legkit.model).

A stance foot that neither lifts nor slips gives the base velocity v = -R (w_b x r + B_J qdot)
(chapters/57.3-leg-kinematics.md, "Leg odometry"); the stance feet's v_i are averaged (the simple
mean of "Several feet in stance")."""
from dataclasses import dataclass

import numpy as np

import legkit


@dataclass
class Comparison:
    """row_velocity over a whole log against its true velocity gt_v."""

    rows_used: int  # rows with at least one foot in contact
    rows_without_contact: int  # skipped rows
    rmse: float  # sqrt(mean |v - gt_v|^2) over the rows used [m/s]
    max_error: float  # max |v - gt_v| over the rows used [m/s]


def row_velocity(R, gyro, q, dq, contact, kin):
    """The mean over the stance legs of v_i = -R (w x r_i + J_i dq_i); None in flight."""
    v = []
    for i in range(4):
        if contact[i]:
            qi, dqi = q[3 * i:3 * i + 3], dq[3 * i:3 * i + 3]
            r, J = kin.foot_position(i, qi), kin.foot_jacobian(i, qi)  # B_p_f and B_J, body frame
            v.append(-R @ (np.cross(gyro, r) + J @ dqi))
    return np.mean(v, axis=0) if v else None


def compare_with_truth(log, kin):
    layout = log.layout
    if not (layout.joints and layout.contact and layout.ground_truth and layout.gt_velocity):
        raise ValueError("compare_with_truth: the log needs joint, contact and ground-truth "
                         "(gt_q, gt_v) columns")
    legs = legkit.model.LEGS
    q = np.stack([log[f"q_{leg}_{j}"] for leg in legs for j in range(3)], -1)
    dq = np.stack([log[f"dq_{leg}_{j}"] for leg in legs for j in range(3)], -1)
    contact = np.stack([log[f"contact_{leg}"] for leg in legs], -1) != 0
    gyro = np.stack([log[f"gyro_{a}"] for a in "xyz"], -1)
    gt_v = np.stack([log[f"gt_v{a}"] for a in "xyz"], -1)
    gt_q = np.stack([log[f"gt_q{a}"] for a in "wxyz"], -1)
    errors = []
    for k in range(len(log)):
        R = legkit.lie.SO3.fromQuaternion(gt_q[k]).matrix()  # body to world
        v = row_velocity(R, gyro[k], q[k], dq[k], contact[k], kin)
        if v is not None:
            errors.append(np.linalg.norm(v - gt_v[k]))
    e = np.array(errors)
    return Comparison(rows_used=len(e), rows_without_contact=len(log) - len(e),
                      rmse=float(np.sqrt(np.mean(e**2))) if len(e) else 0.0,
                      max_error=float(e.max()) if len(e) else 0.0)


def compare_log_file(path, kin):
    return compare_with_truth(legkit.io.read_log(str(path)), kin)
