// legkit.eval: the metrics of `legkit run`'s table (eval/metrics.hpp), NEES and its chi-square
// bounds (eval/consistency.hpp) and the contact scores of 57.6 (eval/contact_scores.hpp).
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "eval/consistency.hpp"
#include "eval/contact_scores.hpp"
#include "eval/metrics.hpp"

namespace py = pybind11;

namespace legkit::python {
namespace {

// A (N, cols) float64 array argument with N rows (N < 0: any).
py::array_t<double, py::array::c_style> rows(py::handle value, const char* name, py::ssize_t n,
                                             py::ssize_t cols) {
  const auto a = float64Array(value, name, cols == 0 ? 1 : 2);
  if ((n >= 0 && a.shape(0) != n) || (cols > 0 && a.shape(1) != cols)) {
    throw py::value_error(std::string(name) + ": expected shape (" +
                          (n >= 0 ? std::to_string(n) : "N") +
                          (cols > 0 ? ", " + std::to_string(cols) : std::string(",")) + ")");
  }
  return a;
}

// An estimate given as a mapping with 't' (N,), 'q' (N, 4: w x y z), 'p' and 'v' (N, 3), as
// legkit.estimators.run returns one per estimator.
eval::Trajectory trajectory(const py::handle& estimate) {
  const auto t = rows(estimate["t"], "estimate['t']", -1, 0);
  const py::ssize_t n = t.shape(0);
  const auto q = rows(estimate["q"], "estimate['q']", n, 4);
  const auto p = rows(estimate["p"], "estimate['p']", n, 3);
  const auto v = rows(estimate["v"], "estimate['v']", n, 3);
  eval::Trajectory x(static_cast<std::size_t>(n));
  for (py::ssize_t k = 0; k < n; ++k) {
    EstimateSample& s = x[static_cast<std::size_t>(k)];
    s.t = t.at(k);
    s.q = Eigen::Quaterniond(q.at(k, 0), q.at(k, 1), q.at(k, 2), q.at(k, 3)).normalized();
    s.p = Eigen::Vector3d(p.at(k, 0), p.at(k, 1), p.at(k, 2));
    s.v = Eigen::Vector3d(v.at(k, 0), v.at(k, 1), v.at(k, 2));
  }
  return x;
}

std::vector<eval::FootFlags> flags(py::handle value, const char* name, py::ssize_t n, int feet) {
  const auto given = py::array::ensure(value);
  const auto a = py::array_t<bool, py::array::c_style>::ensure(value);
  if (!given || given.dtype().kind() != 'b' || !a || a.ndim() != 2 || a.shape(0) != n ||
      a.shape(1) != feet) {
    throw py::value_error(std::string(name) + ": expected a bool array of shape (" +
                          std::to_string(n) + ", feet)");
  }
  std::vector<eval::FootFlags> out(static_cast<std::size_t>(n));
  for (py::ssize_t k = 0; k < n; ++k) {
    for (int f = 0; f < feet; ++f) out[static_cast<std::size_t>(k)][f] = a.at(k, f);
  }
  return out;
}

}  // namespace

void bindEval(py::module_& m) {
  m.def(
      "compare",
      [](const io::Log& log, const py::object& estimate, const std::vector<double>& distances) {
        const eval::Metrics r = eval::compare(log, trajectory(estimate), distances);
        py::list rpe;
        for (const eval::RelativeError& e : r.rpe) {
          rpe.append(py::dict(py::arg("distance") = e.distance, py::arg("pairs") = e.pairs,
                              py::arg("translation_rmse") = e.translation_rmse,
                              py::arg("translation_percent") = e.translation_percent,
                              py::arg("rotation_rmse_deg") = e.rotation_rmse_deg));
        }
        return py::dict(
            py::arg("position_rmse") = r.position_rmse, py::arg("velocity_rmse") = r.velocity_rmse,
            py::arg("final_position_error") = r.final_position_error,
            py::arg("distance") = r.distance, py::arg("drift_percent") = r.drift_percent,
            py::arg("tilt_rmse_deg") = r.tilt_rmse_deg, py::arg("yaw_rmse_deg") = r.yaw_rmse_deg,
            py::arg("ate_rmse") = r.ate_rmse, py::arg("ate_se3_rmse") = r.ate_se3_rmse,
            py::arg("ate_4dof_rmse") = r.ate_4dof_rmse, py::arg("rpe") = rpe,
            py::arg("scored_rows") = r.scored_rows, py::arg("masked_rows") = r.masked_rows,
            py::arg("velocity_method") = r.velocity_method);
      },
      py::arg("log"), py::arg("estimate"), py::arg("rpe_distances") = std::vector<double>{1.0, 5.0},
      "The metrics of `legkit run`'s table: an estimate ({'t', 'q' (N,4 w x y z), 'p', 'v'}, one "
      "row per log row, as estimators.run returns) against the log's truth. Position/velocity "
      "RMSE [m, m/s], drift [% of distance], roll/pitch and yaw RMSE [deg], ATE on the first pose, "
      "after the SE(3) and the 4-DoF alignment [m], RPE per distance [m]. Rows with gt_valid = 0 "
      "are left out; ValueError without a truth or when the rows or times differ");
  m.def(
      "nees",
      [](const EstimateSample& truth, const EstimateSample& estimate, py::handle P,
         bool has_attitude) {
        return eval::nees(truth, estimate, BaseCovariance{fixed<9, 9>(P, "P"), has_attitude});
      },
      py::arg("truth"), py::arg("estimate"), py::arg("P"), py::arg("has_attitude") = true,
      "e^T P^-1 e for e = (dtheta world, dv, dp) (estimation/estimator.hpp's convention); 9 "
      "degrees of freedom, 6 without attitude (rows 3..8 only)");
  m.def("chi_square_quantile", &eval::chiSquareQuantile, py::arg("p"), py::arg("k"),
        "The p-quantile of the chi-square distribution with k degrees of freedom");
  m.def(
      "anees_bounds",
      [](int dof, int runs, double confidence) {
        const eval::ChiSquareBounds b = eval::aneesBounds(dof, runs, confidence);
        return py::make_tuple(b.lower, b.upper);
      },
      py::arg("dof"), py::arg("runs"), py::arg("confidence") = 0.95,
      "(lower, upper): the two-sided acceptance interval of ANEES over `runs` runs of a filter "
      "with `dof` degrees of freedom, [chi2inv((1-c)/2, runs dof), chi2inv((1+c)/2, runs dof)] / "
      "runs");
  m.def(
      "score_contacts",
      [](py::handle t_arg, py::handle detected, py::handle truth) {
        const auto t = rows(t_arg, "t", -1, 0);
        const py::ssize_t n = t.shape(0);
        const auto shape = py::array::ensure(detected);
        if (!shape || shape.ndim() != 2 || shape.shape(1) < 1 ||
            shape.shape(1) > eval::kScoredFeet) {
          throw py::value_error("detected: expected a bool array of shape (N, feet), feet 1..8");
        }
        const int feet = static_cast<int>(shape.shape(1));
        const std::vector<eval::FootFlags> d = flags(detected, "detected", n, feet);
        const std::vector<eval::FootFlags> g = flags(truth, "truth", n, feet);
        const eval::ContactScores s =
            eval::scoreContacts(std::vector<double>(t.data(), t.data() + n), d, g, feet);
        return py::dict(
            py::arg("precision") = s.precision, py::arg("recall") = s.recall, py::arg("f1") = s.f1,
            py::arg("touchdown_delay_mean") = s.touchdown_delay_mean,
            py::arg("touchdown_delay_p95") = s.touchdown_delay_p95,
            py::arg("liftoff_delay_mean") = s.liftoff_delay_mean,
            py::arg("liftoff_delay_p95") = s.liftoff_delay_p95,
            py::arg("chatter_per_min") = s.chatter_per_min, py::arg("touchdowns") = s.touchdowns,
            py::arg("liftoffs") = s.liftoffs, py::arg("missed_touchdowns") = s.missed_touchdowns,
            py::arg("missed_liftoffs") = s.missed_liftoffs,
            py::arg("spurious_toggles") = s.spurious_toggles);
      },
      py::arg("t"), py::arg("detected"), py::arg("truth"),
      "Contact detection scored against the truth (57.6): precision, recall, F1, touchdown and "
      "lift-off delays [ms] (events matched within +-100 ms), chatter [toggles/min]. t (N,) [s], "
      "detected and truth (N, feet) bool");
}

}  // namespace legkit::python
