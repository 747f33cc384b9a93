// The Python module legkit (pybind11): one binding function per submodule, each in its own file,
// all over the same C++ the command line runs (no second implementation).
#pragma once

#include <pybind11/pybind11.h>

namespace legkit::python {

void bindLie(pybind11::module_& m);         // legkit.lie: SO3, SE3, SE_K(3), the IMU model
void bindIo(pybind11::module_& m);          // legkit.io: the log format
void bindModel(pybind11::module_& m);       // legkit.model: the built-in quadruped's kinematics
void bindContact(pybind11::module_& m);     // legkit.contact: detectors, logistic model
void bindEstimators(pybind11::module_& m);  // legkit.estimators: the estimators, settings, run
void bindEval(pybind11::module_& m);        // legkit.eval: RMSE, ATE/RPE, NEES, contact scores
void bindSim(pybind11::module_& m);         // legkit.sim: the scenarios to a log in memory

}  // namespace legkit::python
