// legkit.contact: the contact detectors of section 57.6 by name (estimation/contact/detectors.hpp)
// run over a log, and method 5, the logistic contact probability
//   p_c = sigma(w1 F_n + w2 |v_foot| + w3 phi + b)                                 (57.6, m. 5)
// its model (estimation/contact/logistic_contact.hpp), its training samples from a physics log
// (eval/contact_training.hpp) and the kit's Newton trainer (logistic_training.hpp).
// Features are (N, 3) float64 arrays, one row per sample: force F_n [N], foot speed |v_foot|
// [m/s], planned gait phase phi in [0, 1).
#include <pybind11/stl.h>

#include <cmath>
#include <map>

#include "arrays.hpp"
#include "bindings.hpp"
#include "estimation/contact/detectors.hpp"
#include "estimation/contact/logistic_training.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/contact_training.hpp"
#include "sim/physics_scenario.hpp"

namespace py = pybind11;

namespace legkit::python {
namespace {

using contact::ContactFeatures;
using contact::GaitSchedule;
using contact::LogisticModel;

py::array_t<double> featureArray(const std::vector<ContactFeatures>& x) {
  py::array_t<double> out({static_cast<py::ssize_t>(x.size()), py::ssize_t{3}});
  auto v = out.mutable_unchecked<2>();
  for (py::ssize_t n = 0; n < v.shape(0); ++n) {
    const ContactFeatures& f = x[static_cast<std::size_t>(n)];
    v(n, 0) = f.force;
    v(n, 1) = f.foot_speed;
    v(n, 2) = f.phase;
  }
  return out;
}

std::vector<ContactFeatures> features(py::handle value) {
  const auto a = float64Array(value, "features", 2);
  if (a.shape(1) != 3) {
    throw py::value_error("features: expected shape (N, 3) (force, foot_speed, phase), got (" +
                          std::to_string(a.shape(0)) + ", " + std::to_string(a.shape(1)) + ")");
  }
  std::vector<ContactFeatures> x(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t n = 0; n < a.shape(0); ++n) {
    x[static_cast<std::size_t>(n)] = {a.at(n, 0), a.at(n, 1), a.at(n, 2)};
  }
  return x;
}

// Labels (N,): bool, or numbers that are each 0 or 1.
std::vector<bool> labels(py::handle value) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 1) throw py::value_error("labels: expected a 1-D array of bool or 0/1");
  std::vector<bool> y(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t n = 0; n < a.shape(0); ++n) {
    if (a.at(n) != 0.0 && a.at(n) != 1.0) {
      throw py::value_error("labels: entry " + std::to_string(n) + " is " +
                            std::to_string(a.at(n)) + ", expected 0 or 1");
    }
    y[static_cast<std::size_t>(n)] = a.at(n) == 1.0;
  }
  return y;
}

// Every row of `log` through the detector `name`, as the pipeline hands it a row
// (LogFrontend::signals), with the row's true base state as the previous estimate (a perfect
// estimator, eval::truthFeedback) where the log has a valid truth.
py::dict detect(const io::Log& log, const std::string& name,
                const std::optional<GaitSchedule>& gait, const std::optional<LogisticModel>& model,
                double hysteresis, const model::QuadrupedKinematics& kinematics) {
  contact::DetectorContext context;
  context.geometry = kinematics.geometry();
  context.gait = gait;
  context.logistic = model;
  context.probabilistic.hysteresis = hysteresis;
  const std::unique_ptr<contact::ContactDetector> detector = contact::makeDetector(name, context);
  const LogFrontend frontend(log.layout, kinematics);
  const auto n = static_cast<py::ssize_t>(log.rows.size());
  const py::ssize_t feet = log.layout.num_feet;
  py::array_t<double> t(n), probability({n, feet});
  py::array_t<bool> contact({n, feet}), usable({n, feet});
  auto tv = t.mutable_unchecked<1>();
  auto pv = probability.mutable_unchecked<2>();
  auto cv = contact.mutable_unchecked<2>();
  auto uv = usable.mutable_unchecked<2>();
  std::map<std::string, int> problems;
  for (py::ssize_t k = 0; k < n; ++k) {
    const io::LogRow& row = log.rows[static_cast<std::size_t>(k)];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[static_cast<std::size_t>(k - 1)].t;
    const contact::BaseFeedback base = log.layout.ground_truth && row.gt_valid
                                           ? eval::truthFeedback(row)
                                           : contact::BaseFeedback{};
    const contact::ContactEstimate e = detector->update(frontend.signals(row, dt, base));
    tv(k) = row.t;
    for (py::ssize_t f = 0; f < feet; ++f) {
      const contact::FootContact& c = e.feet[static_cast<std::size_t>(f)];
      uv(k, f) = c.usable();
      cv(k, f) = c.usable() && c.contact;
      pv(k, f) = c.usable() ? c.probability : std::nan("");
      if (!c.usable()) ++problems[c.problem];
    }
  }
  py::dict d;
  d["t"] = t;
  d["contact"] = contact;
  d["probability"] = probability;
  d["usable"] = usable;
  d["problems"] = problems;
  return d;
}

}  // namespace

void bindContact(py::module_& m) {
  m.def("detector_names", &contact::detectorNames,
        "The contact detectors of 57.6 by name, as `legkit run --contact NAME` takes them");

  py::class_<GaitSchedule>(
      m, "GaitSchedule",
      "A robot's planned gait (estimation/contact/gait_schedule.hpp): foot i is planned in "
      "stance while frac((t - start) / period - offset_i) < duty; every foot stands before start")
      .def_readonly("period", &GaitSchedule::period, "[s]")
      .def_readonly("duty", &GaitSchedule::duty, "planned stance fraction of the period")
      .def_readonly("start", &GaitSchedule::start, "when the clock starts [s]")
      .def_readonly("num_feet", &GaitSchedule::num_feet)
      .def_property_readonly(
          "offset",
          [](const GaitSchedule& g) { return py::array_t<double>(g.num_feet, g.offset.data()); },
          "(num_feet,): each foot's phase offset [periods]")
      .def(
          "phase",
          [](const GaitSchedule& g, int foot, double t) {
            if (foot < 0 || foot >= g.num_feet) {
              throw py::value_error("foot " + std::to_string(foot) + " outside 0.." +
                                    std::to_string(g.num_feet - 1));
            }
            return contact::plannedPhase(g, foot, t);
          },
          py::arg("foot"), py::arg("t"),
          "The planned phase phi in [0, 1) of `foot` at t [s]: 0 at the planned touchdown, "
          "stance below duty (0 before the foot's first planned lift-off)");
  m.def(
      "planned_gait",
      [](const std::string& scenario) {
        return eval::plannedGait(sim::physicsScenarioByName(scenario));
      },
      py::arg("scenario") = "physics-trot",
      "The gait a robot running the physics scenario would publish: its gait, the clock "
      "started at the end of its stand");

  py::class_<LogisticModel>(
      m, "LogisticModel",
      "The logistic contact probability of 57.6, method 5: p_c = sigma(w . (1, x_scaled)) with "
      "x_scaled = (x - mean) / scale for x = (force [N], foot_speed [m/s], phase). A weight of "
      "exactly 0: the model does not use that feature")
      .def(py::init([](py::handle w, py::handle mean, py::handle scale) {
             LogisticModel model;
             model.w = fixed<4>(w, "w");
             model.mean = fixed<3>(mean, "mean");
             model.scale = fixed<3>(scale, "scale");
             return model;
           }),
           py::arg("w"), py::arg("mean") = std::array<double, 3>{},
           py::arg("scale") = std::array<double, 3>{1.0, 1.0, 1.0},
           "w (4,) = (b, w_F, w_v, w_phi) on the scaled features; mean (3,) and scale (3,) the "
           "training set's per-feature mean and standard deviation")
      .def_property_readonly(
          "w", [](const LogisticModel& x) { return py::array_t<double>(4, x.w.data()); },
          "(4,): (b, w_F, w_v, w_phi), on the scaled features")
      .def_property_readonly(
          "mean", [](const LogisticModel& x) { return py::array_t<double>(3, x.mean.data()); },
          "(3,): feature means (force [N], foot_speed [m/s], phase)")
      .def_property_readonly(
          "scale", [](const LogisticModel& x) { return py::array_t<double>(3, x.scale.data()); },
          "(3,): feature standard deviations (same units)")
      .def_property_readonly("uses_force", &LogisticModel::usesForce)
      .def_property_readonly("uses_foot_speed", &LogisticModel::usesFootSpeed)
      .def_property_readonly("uses_phase", &LogisticModel::usesPhase)
      .def(
          "probability",
          [](const LogisticModel& model, py::handle x) {
            const std::vector<ContactFeatures> samples = features(x);
            py::array_t<double> p(static_cast<py::ssize_t>(samples.size()));
            for (std::size_t n = 0; n < samples.size(); ++n) {
              p.mutable_at(static_cast<py::ssize_t>(n)) =
                  contact::contactProbability(model, samples[n]);
            }
            return p;
          },
          py::arg("features"),
          "p_c (N,) of features (N, 3); NaN where a feature the model uses is NaN")
      .def("__repr__", [](const py::object& x) {
        return py::str("LogisticModel(w={}, mean={}, scale={})")
            .format(x.attr("w"), x.attr("mean"), x.attr("scale"));
      });

  m.def(
      "training_samples",
      [](const io::Log& log, const std::optional<GaitSchedule>& gait,
         const model::QuadrupedKinematics& kinematics) {
        std::vector<ContactFeatures> x;
        std::vector<bool> y;
        eval::appendTrainingSamples(log, gait ? &*gait : nullptr, kinematics, x, y);
        py::array_t<bool> labels(static_cast<py::ssize_t>(y.size()));
        for (std::size_t n = 0; n < y.size(); ++n)
          labels.mutable_at(static_cast<py::ssize_t>(n)) = y[n];
        return py::make_tuple(featureArray(x), labels);
      },
      py::arg("log"), py::arg("gait") = py::none(),
      py::arg_v("kinematics", model::QuadrupedKinematics(), "QuadrupedKinematics()"),
      "(features (4N, 3), labels (4N,) bool): one sample per row and foot (sample 4 k + foot) of "
      "a physics log, the features as the detector computes them (the foot speed from the row's "
      "true base velocity and attitude, the phase from `gait` or 0), the label the foot's true "
      "contact (gt_contact_*). ValueError for a log without joint, force, ground-truth or "
      "contact-truth columns");
  m.def(
      "train_logistic",
      [](py::handle x, py::handle y, double l2, int max_iterations, double tolerance,
         bool use_force, bool use_foot_speed, bool use_phase) {
        contact::TrainingOptions options;
        options.l2 = l2;
        options.max_iterations = max_iterations;
        options.tolerance = tolerance;
        options.use_force = use_force;
        options.use_foot_speed = use_foot_speed;
        options.use_phase = use_phase;
        return contact::trainLogistic(features(x), labels(y), options);
      },
      py::arg("features"), py::arg("labels"), py::arg("l2") = 1e-3, py::arg("max_iterations") = 50,
      py::arg("tolerance") = 1e-10, py::arg("use_force") = true, py::arg("use_foot_speed") = true,
      py::arg("use_phase") = true,
      "The kit's fit (logistic_training.hpp): features scaled by their mean and standard "
      "deviation (over n), then Newton steps (X^T W X + l2 I') dw = -(X^T (p - y) + l2 I' w) from "
      "the labels' log-odds until the largest step component is below `tolerance`. A feature "
      "switched off or constant gets weight 0. ValueError (saying which) for no samples, labels "
      "of one class, a used feature not finite, bad options");
  m.def(
      "train_contact_model",
      [](unsigned seed) {
        py::gil_scoped_release release;
        return eval::trainContactModel(seed);
      },
      py::arg("seed") = 1,
      "The kit's model, as `legkit run --contact probabilistic` trains it: physics-trot, -walk "
      "and -ice for 10 s each with seeds seed + 1000.. + 1002 (about 2 s; the GIL is "
      "released)");

  m.def("detect", &detect, py::arg("log"), py::arg("detector"), py::arg("gait") = py::none(),
        py::arg("model") = py::none(), py::arg("hysteresis") = 0.4,
        py::arg_v("kinematics", model::QuadrupedKinematics(), "QuadrupedKinematics()"),
        "Runs the contact detector `detector` (detector_names()) over every row of a quadruped "
        "log, as the run pipeline hands it each row, with the row's true base state as the "
        "previous estimate (a perfect estimator; none on a log without truth). `gait`: the "
        "planned gait (gait-clock, fallback, a model that uses the phase); `model`: the "
        "LogisticModel of 'probabilistic', whose contact turns on above p_c = 0.5 + hysteresis "
        "and off below 0.5 - hysteresis. Returns {'t' (N,), 'contact' (N, feet) bool, "
        "'probability' (N, feet) p_c, 'usable' (N, feet) bool, 'problems' {why: count}}; where "
        "a foot is not usable (the detector could not decide) contact is False and p_c NaN. "
        "ValueError for an unknown name or a context the detector lacks");
}

}  // namespace legkit::python
