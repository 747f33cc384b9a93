// legkit._core: the compiled half of the Python package legkit (python/legkit/__init__.py makes
// its submodules importable as legkit.lie, legkit.io, ...).
#include "bindings.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "legkit: Lie groups and legged-robot state estimation (the C++ kit, from Python)";
  m.attr("__version__") = LEGKIT_VERSION;
  // Order matters: io's Log is used by sim, estimators and eval; estimators' types by eval.
  auto lie = m.def_submodule("lie", "SO(3), SE(3), SE_K(3) and the IMU model (lie/, chapter 00)");
  legkit::python::bindLie(lie);
  auto io = m.def_submodule("io", "The log format of chapter 57.0: read, write, columns");
  legkit::python::bindIo(io);
  auto model = m.def_submodule("model", "The built-in Go2-class quadruped's kinematics (57.3)");
  legkit::python::bindModel(model);
  auto contact =
      m.def_submodule("contact", "Contact detectors and the logistic contact model (57.6)");
  legkit::python::bindContact(contact);
  auto sim = m.def_submodule("sim", "The analytic and physics scenarios of 57.0, to a log");
  legkit::python::bindSim(sim);
  auto estimators = m.def_submodule(
      "estimators", "Every estimator of 57.3-57.8 behind one interface, settings, whole-log run");
  legkit::python::bindEstimators(estimators);
  auto eval = m.def_submodule("eval", "RMSE, ATE/RPE, NEES with chi-square bounds, contact scores");
  legkit::python::bindEval(eval);
}
