// legkit.model: the built-in Go2-class quadruped's kinematics (model/quadruped.hpp, section 57.3):
// forward kinematics B_p_f = FK(q), the body-frame foot Jacobian B_J = d FK / dq and inverse
// kinematics of each leg, in the body (IMU) frame: x forward, y left, z up.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "model/quadruped.hpp"

namespace py = pybind11;

namespace legkit::python {
namespace {

using model::QuadrupedGeometry;
using model::QuadrupedKinematics;
using PerLeg = std::array<Eigen::Vector3d, model::kNumLegs>;

// One vector per leg as a (4, 3) array, row = leg id, and back.
py::array_t<double> perLegArray(const PerLeg& x) {
  Eigen::Matrix<double, model::kNumLegs, 3> m;
  for (int leg = 0; leg < model::kNumLegs; ++leg) m.row(leg) = x[leg].transpose();
  return toArray(m);
}
PerLeg perLeg(py::handle value, const char* name) {
  const Eigen::Matrix<double, model::kNumLegs, 3> m = fixed<model::kNumLegs, 3>(value, name);
  PerLeg x;
  for (int leg = 0; leg < model::kNumLegs; ++leg) x[leg] = m.row(leg).transpose();
  return x;
}

// A read-write (4, 3) property over one of the geometry's per-leg members.
template <PerLeg QuadrupedGeometry::*member>
void perLegProperty(py::class_<QuadrupedGeometry>& c, const char* name, const char* doc) {
  c.def_property(
      name, [](const QuadrupedGeometry& g) { return perLegArray(g.*member); },
      [name](QuadrupedGeometry& g, py::handle value) { g.*member = perLeg(value, name); }, doc);
}

}  // namespace

void bindModel(py::module_& m) {
  py::tuple legs(model::kNumLegs);
  for (int leg = 0; leg < model::kNumLegs; ++leg) legs[leg] = model::legName(leg);
  m.attr("LEGS") = legs;
  m.def("leg_name", &model::legName, py::arg("leg"),
        "The name of leg id 0..3: 'FL', 'FR', 'RL', 'RR' (the order of logs and contacts)");

  py::class_<QuadrupedGeometry> geometry(
      m, "QuadrupedGeometry",
      "A quadruped's leg geometry (model/quadruped.hpp): three revolute joints per leg, hip "
      "abduction about body x, hip flexion and knee about the thigh's and calf's y; at q = 0 the "
      "leg hangs straight down. QuadrupedGeometry() is the Unitree Go2's; change the fields for "
      "your own robot (QuadrupedKinematics checks them)");
  geometry.def(py::init(&QuadrupedGeometry::go2), "The Go2-class numbers")
      .def_readwrite("abduction_offset", &QuadrupedGeometry::abduction_offset,
                     "abduction axis to the thigh plane, outward positive (+y left legs, -y right "
                     "legs, before the abduction rotation) [m]")
      .def_readwrite("thigh_length", &QuadrupedGeometry::thigh_length,
                     "hip-flexion axis to knee axis [m]")
      .def_readwrite("calf_length", &QuadrupedGeometry::calf_length,
                     "knee axis to the centre of the foot sphere (the foot point) [m]")
      .def_readwrite("foot_radius", &QuadrupedGeometry::foot_radius,
                     "radius of the foot sphere [m]")
      .def(
          "within_limits",
          [](const QuadrupedGeometry& g, int leg, py::handle q, double tol) {
            return g.withinLimits(leg, fixed<3>(q, "q"), tol);
          },
          py::arg("leg"), py::arg("q"), py::arg("tol") = 0.0,
          "Whether every joint angle of q (3,) [rad] lies within the leg's limits (inclusive, "
          "widened by tol [rad])");
  perLegProperty<&QuadrupedGeometry::hip_offset>(
      geometry, "hip_offset",
      "(4, 3): each hip (the abduction axis) in the body frame [m], row = leg");
  perLegProperty<&QuadrupedGeometry::q_min>(
      geometry, "q_min", "(4, 3): lower joint limits (abduction, hip, knee) per leg [rad]");
  perLegProperty<&QuadrupedGeometry::q_max>(
      geometry, "q_max", "(4, 3): upper joint limits (abduction, hip, knee) per leg [rad]");

  py::class_<QuadrupedKinematics>(
      m, "QuadrupedKinematics",
      "Kinematics of each leg of a quadruped (57.3), in the body frame (the IMU frame: x forward, "
      "y left, z up). leg: 0 FL, 1 FR, 2 RL, 3 RR; q: the leg's (abduction, hip, knee) angles "
      "[rad]. ValueError for a leg outside 0..3 or a non-finite angle")
      .def(py::init<const QuadrupedGeometry&>(),
           py::arg_v("geometry", QuadrupedGeometry::go2(), "QuadrupedGeometry()"),
           "ValueError for a geometry with a non-positive link, a non-finite number or a lower "
           "limit above an upper one")
      .def(
          "foot_position",
          [](const QuadrupedKinematics& k, int leg, py::handle q) {
            return toArray(k.footPosition(leg, fixed<3>(q, "q")));
          },
          py::arg("leg"), py::arg("q"),
          "B_p_f = FK(q) (3,): the foot point (centre of the foot sphere) in the body frame [m]")
      .def(
          "foot_jacobian",
          [](const QuadrupedKinematics& k, int leg, py::handle q) {
            return toArray(k.footJacobian(leg, fixed<3>(q, "q")));
          },
          py::arg("leg"), py::arg("q"),
          "B_J = d FK / dq (3, 3), analytic: B_J @ dq is the foot's velocity relative to the "
          "body, in the body frame [m/s] for joint rates dq [rad/s]")
      .def(
          "inverse_kinematics",
          [](const QuadrupedKinematics& k, int leg, py::handle p_body) {
            return toArray(k.inverseKinematics(leg, fixed<3>(p_body, "p_body")));
          },
          py::arg("leg"), py::arg("p_body"),
          "The joint angles (3,) [rad] that put the foot point at p_body (body frame) [m], on the "
          "Go2 branch (knee negative, pointing back); ValueError naming the leg and the point "
          "when none within the joint limits exists")
      .def_property_readonly(
          "geometry", [](const QuadrupedKinematics& k) { return k.geometry(); },
          "its QuadrupedGeometry (a copy)");
}

}  // namespace legkit::python
