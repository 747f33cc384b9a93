"""legkit: Lie groups and legged-robot state estimation, from Python.

The same C++ as the command line (pybind11), in seven submodules:
  legkit.lie         SO3, SE3, SE_K(3), the IMU model (chapter 00)
  legkit.io          the log format (chapter 57.0)
  legkit.model       the built-in quadruped's kinematics (57.3)
  legkit.contact     contact detectors and the logistic contact model (57.6)
  legkit.sim         the analytic and physics scenarios, to a log in memory
  legkit.estimators  every estimator behind one interface, settings, the whole-log run
  legkit.eval        RMSE, ATE/RPE, NEES with chi-square bounds, contact scores

From the build tree: PYTHONPATH=build/python python3 -c "import legkit".
"""
import sys as _sys

from . import _core

__version__ = _core.__version__
lie = _core.lie
io = _core.io
model = _core.model
contact = _core.contact
sim = _core.sim
estimators = _core.estimators
eval = _core.eval  # noqa: A001 (the C++ layer's name)

# `import legkit.lie` and `from legkit.lie import SO3` find the compiled submodules.
for _name in ("lie", "io", "model", "contact", "sim", "estimators", "eval"):
    _sys.modules[__name__ + "." + _name] = getattr(_core, _name)
_sys.modules[__name__ + ".lie.imu"] = _core.lie.imu
