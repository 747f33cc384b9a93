"""Exercise 57.3.3 in Python: leg odometry over a simulated log, compared with its truth.

Replace each `raise NotImplementedError(...)` with NumPy code. The kinematics and the log come
from the kit's C++ through the Python package: legkit.model.QuadrupedKinematics (foot_position,
foot_jacobian), legkit.io.Log (log['q_FL_0'] is a column as an array, log.layout says which
column groups it has). The task, the tests and the hints: ../README.md, "Python variant".
Run the tests: tools/exercise 57.3.3 --python
"""
from dataclasses import dataclass

import numpy as np  # you will need it

import legkit  # legkit.io.read_log, legkit.model.LEGS

STUB = "exercises/ex57_3_3_log_leg_odometry/python/exercise.py"


@dataclass
class Comparison:
    """row_velocity over a whole log against its true velocity gt_v."""

    rows_used: int  # rows with at least one foot in contact
    rows_without_contact: int  # skipped rows
    rmse: float  # sqrt(mean |v - gt_v|^2) over the rows used [m/s]
    max_error: float  # max |v - gt_v| over the rows used [m/s]


def row_velocity(R, gyro, q, dq, contact, kin):
    """The world-frame base velocity of one log row, (3,) [m/s]; None when no foot is in contact.

    For every leg i (0 FL, 1 FR, 2 RL, 3 RR) whose contact flag is set,
        v_i = -R (w x r_i + J_i dq_i)
    with r_i = kin.foot_position(i, q_i), J_i = kin.foot_jacobian(i, q_i), q_i = q[3i:3i+3] and
    dq_i = dq[3i:3i+3]; the answer is the mean of the v_i.
      R        (3, 3) the attitude, body to world (the row's gt_q; an attitude filter comes in 57.4)
      gyro     (3,) w, the body angular rate [rad/s] (body frame)
      q, dq    (12,) joint angles [rad] and rates [rad/s], three per leg, legs FL FR RL RR
      contact  (4,) bool, the contact flag of each leg
      kin      a legkit.model.QuadrupedKinematics
    """
    raise NotImplementedError(f"row_velocity: not implemented yet ({STUB})")


def compare_with_truth(log, kin):
    """row_velocity over every row of a legkit.io.Log against its gt_v: a Comparison.

    Rows without contact are counted and left out of the RMSE and the largest error. ValueError
    when the log lacks joint columns, contact flags or the true attitude and velocity (gt_q*,
    gt_v*).
    """
    raise NotImplementedError(f"compare_with_truth: not implemented yet ({STUB})")


def compare_log_file(path, kin):
    """compare_with_truth for the CSV log at `path` (legkit.io.read_log)."""
    raise NotImplementedError(f"compare_log_file: not implemented yet ({STUB})")
