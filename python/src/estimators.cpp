// legkit.estimators: every estimator of chapter 57 behind its one interface
// (estimation/estimator.hpp), the settings file (estimation/settings.hpp), the estimator manager
// of 57.11 (estimation/state_estimator.hpp) and the whole-log run of `legkit run` (eval/runner.hpp)
// as NumPy arrays.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "estimation/contact/detectors.hpp"
#include "estimation/estimators.hpp"
#include "estimation/log_conditioning.hpp"
#include "estimation/settings.hpp"
#include "estimation/slip/slip_detector.hpp"
#include "estimation/state_estimator.hpp"
#include "eval/contact_training.hpp"
#include "eval/log_run.hpp"
#include "eval/runner.hpp"
#include "io/yaml_reader.hpp"
#include "model/mujoco_kinematics.hpp"
#include "model/quadruped.hpp"

namespace py = pybind11;

namespace legkit::python {
namespace {

// Quaternion (w, x, y, z) <-> Eigen.
py::array_t<double> wxyz(const Eigen::Quaterniond& q) {
  return py::array_t<double>(4, std::array<double, 4>{q.w(), q.x(), q.y(), q.z()}.data());
}
Eigen::Quaterniond quaternion(py::handle value, const char* name) {
  const Eigen::Vector4d q = fixed<4>(value, name);
  if (!q.allFinite() || std::abs(q.norm() - 1.0) > 1e-6) {
    throw py::value_error(std::string(name) + ": expected a finite unit quaternion (w, x, y, z)");
  }
  return Eigen::Quaterniond(q(0), q(1), q(2), q(3));
}

// The non-zero fault counts of a Health, by the fault's name (estimation/health.hpp).
py::dict faults(const Health& h) {
  py::dict d;
  for (int f = 0; f < static_cast<int>(Fault::kCount); ++f) {
    if (h.count[f] > 0) d[faultName(static_cast<Fault>(f))] = h.count[f];
  }
  return d;
}

// One step's input from Python: the contacts are ContactMeasurement objects.
StepInput stepInput(double t, double dt, py::handle gyro, py::handle acc,
                    const std::vector<ContactMeasurement>& contacts,
                    const std::optional<std::vector<double>>& normal_force) {
  StepInput in;
  in.t = t;
  in.dt = dt;
  in.imu.w_m = fixed<3>(gyro, "gyro");
  in.imu.a_m = fixed<3>(acc, "acc");
  if (contacts.size() > in.contacts.size()) {
    throw py::value_error("contacts: at most " + std::to_string(in.contacts.size()) +
                          " feet, got " + std::to_string(contacts.size()));
  }
  for (std::size_t k = 0; k < contacts.size(); ++k) in.contacts[k] = contacts[k];
  in.num_contacts = static_cast<int>(contacts.size());
  if (normal_force) {
    if (normal_force->size() != contacts.size()) {
      throw py::value_error("normal_force: one per contact, got " +
                            std::to_string(normal_force->size()) + " for " +
                            std::to_string(contacts.size()));
    }
    std::copy(normal_force->begin(), normal_force->end(), in.normal_force.begin());
    in.has_force = true;
  }
  return in;
}

// A run's arrays: t, q (N, 4: w x y z), p, v (N, 3), sigma (N, 9) and nees (N) for a filter,
// contacts (N, feet), its health and failure, and its start.
py::dict runArrays(const eval::RunResult& run, int num_feet) {
  const auto n = static_cast<py::ssize_t>(run.trajectory.size());
  py::array_t<double> t(n), q({n, py::ssize_t{4}}), p({n, py::ssize_t{3}}), v({n, py::ssize_t{3}});
  auto tv = t.mutable_unchecked<1>();
  auto qv = q.mutable_unchecked<2>();
  auto pv = p.mutable_unchecked<2>();
  auto vv = v.mutable_unchecked<2>();
  for (py::ssize_t k = 0; k < n; ++k) {
    const EstimateSample& x = run.trajectory[static_cast<std::size_t>(k)];
    tv(k) = x.t;
    const Eigen::Vector4d c = x.q.coeffs();  // x y z w
    qv(k, 0) = c(3);
    for (int i = 0; i < 3; ++i) {
      qv(k, i + 1) = c(i);
      pv(k, i) = x.p(i);
      vv(k, i) = x.v(i);
    }
  }
  py::dict d;
  d["name"] = run.name;
  d["t"] = t;
  d["q"] = q;
  d["p"] = p;
  d["v"] = v;
  if (!run.sigma.empty()) {
    py::array_t<double> s({static_cast<py::ssize_t>(run.sigma.size()), py::ssize_t{9}});
    auto sv = s.mutable_unchecked<2>();
    for (std::size_t k = 0; k < run.sigma.size(); ++k) {
      for (int i = 0; i < 9; ++i) sv(static_cast<py::ssize_t>(k), i) = run.sigma[k](i);
    }
    d["sigma"] = s;
  } else {
    d["sigma"] = py::none();
  }
  d["nees"] = run.nees.empty() ? py::object(py::none())
                               : py::object(py::array_t<double>(
                                     static_cast<py::ssize_t>(run.nees.size()), run.nees.data()));
  d["nees_dof"] = run.nees_dof;
  if (!run.detected_contact.empty()) {
    py::array_t<bool> c({static_cast<py::ssize_t>(run.detected_contact.size()),
                         static_cast<py::ssize_t>(num_feet)});
    auto cv = c.mutable_unchecked<2>();
    for (std::size_t k = 0; k < run.detected_contact.size(); ++k) {
      for (int f = 0; f < num_feet; ++f)
        cv(static_cast<py::ssize_t>(k), f) = run.detected_contact[k][f];
    }
    d["contacts"] = c;
  }
  if (!run.slip.empty()) {  // the slip check of 57.7 on each row, whatever the reaction
    const auto rows = static_cast<py::ssize_t>(run.slip.size());
    py::array_t<int> checked(rows), slipping(rows), outlier(rows);
    py::array_t<bool> all(rows);
    for (py::ssize_t k = 0; k < rows; ++k) {
      const eval::SlipSummary& s = run.slip[static_cast<std::size_t>(k)];
      checked.mutable_at(k) = s.checked;
      slipping.mutable_at(k) = s.slipping;
      outlier.mutable_at(k) = s.outlier;
      all.mutable_at(k) = s.all_slipping;
    }
    d["slip"] = py::dict(py::arg("checked") = checked, py::arg("slipping") = slipping,
                         py::arg("all_slipping") = all, py::arg("outlier") = outlier,
                         py::arg("reaction") = run.slip_reaction);
  }
  d["contact_source"] = run.contact_source;
  d["health"] = faults(run.health);
  d["healthy"] = run.ok();
  d["failure"] = run.failure ? py::object(py::str(eval::describe(*run.failure))) : py::none();
  d["us_per_step"] = run.us_per_step;
  // How its gyro bias started (initialisation.gyro_bias: still-window), as legkit run's start:
  // line.
  d["start"] = run.start.empty() ? py::object(py::none()) : py::object(py::str(run.start));
  return d;
}

// The estimator manager's samples from Python: joint angles and rates (count = the robot's
// joints), optional forces and flags per foot.
JointSample jointSample(py::handle q, py::handle dq, bool valid) {
  const auto qa = float64Array(q, "q", 1);
  const auto dqa = float64Array(dq, "dq", 1);
  if (qa.shape(0) != dqa.shape(0) || qa.shape(0) > io::kMaxJoints) {
    throw py::value_error("q, dq: expected two arrays of the robot's joint count (at most " +
                          std::to_string(io::kMaxJoints) + "), got " + std::to_string(qa.shape(0)) +
                          " and " + std::to_string(dqa.shape(0)));
  }
  JointSample j;
  j.count = static_cast<int>(qa.shape(0));
  for (int k = 0; k < j.count; ++k) {
    j.q(k) = qa.at(k);
    j.dq(k) = dqa.at(k);
  }
  j.valid = valid;
  return j;
}
ForceSample forceSample(py::handle force, py::handle contact) {
  ForceSample f;
  if (!force.is_none()) {
    const auto a = float64Array(force, "force", 1);
    if (a.shape(0) > io::kMaxFeet) throw py::value_error("force: at most 6 feet");
    for (py::ssize_t k = 0; k < a.shape(0); ++k) f.force[static_cast<std::size_t>(k)] = a.at(k);
    f.valid = true;
  }
  if (!contact.is_none()) {
    const auto flags = py::cast<std::vector<bool>>(contact);
    if (flags.size() > io::kMaxFeet) throw py::value_error("contact: at most 6 feet");
    std::copy(flags.begin(), flags.end(), f.contact.begin());
  }
  return f;
}

py::dict outputDict(const EstimatorOutput& o) {
  py::dict d;
  d["x"] = o.x;
  d["P"] = o.has_covariance ? py::object(toArray(o.P.P)) : py::none();
  py::list contact, probability;
  for (int f = 0; f < o.contacts.num_feet; ++f) {
    contact.append(o.contacts.feet[f].contact);
    probability.append(o.contacts.feet[f].probability);
  }
  d["contact"] = contact;
  d["probability"] = probability;
  d["health"] = faults(o.health);
  d["initialised"] = o.initialised;
  d["initialising"] = o.initialising;
  d["start"] = startModeName(o.start);
  py::list alarms;
  for (int a = 0; a < engineering::kNumAlarms; ++a) {
    if (o.monitors.active[a])
      alarms.append(engineering::alarmName(static_cast<engineering::Alarm>(a)));
  }
  d["alarms"] = alarms;
  d["uncertain"] = o.monitors.uncertain;
  return d;
}

}  // namespace

void bindEstimators(py::module_& m) {
  // A settings file's error (io::ConfigError: file, line, key) is a ValueError.
  py::register_exception<io::ConfigError>(m, "SettingsError", PyExc_ValueError);
  py::class_<EstimateSample>(m, "EstimateSample",
                             "The base state at time t (estimation/estimate.hpp): q the attitude "
                             "body to world as (w, x, y, z), v the world velocity [m/s], p the "
                             "world position [m]")
      .def(py::init([](double t, py::handle q, py::handle v, py::handle p) {
             EstimateSample x;
             x.t = t;
             x.q = quaternion(q, "q");
             x.v = fixed<3>(v, "v");
             x.p = fixed<3>(p, "p");
             return x;
           }),
           py::arg("t") = 0.0, py::arg("q") = std::array<double, 4>{1, 0, 0, 0},
           py::arg("v") = std::array<double, 3>{}, py::arg("p") = std::array<double, 3>{})
      .def_readonly("t", &EstimateSample::t)
      .def_property_readonly("q", [](const EstimateSample& x) { return wxyz(x.q); })
      .def_property_readonly(
          "R", [](const EstimateSample& x) { return toArray(x.q.toRotationMatrix()); },
          "the attitude as a rotation matrix, body to world")
      .def_property_readonly("v", [](const EstimateSample& x) { return toArray(x.v); })
      .def_property_readonly("p", [](const EstimateSample& x) { return toArray(x.p); });

  py::class_<ContactMeasurement>(m, "ContactMeasurement",
                                 "A foot seen from the body (model/contact_measurement.hpp)")
      .def(py::init([](int foot, py::handle p_body, py::handle cov, py::handle v_body,
                       double probability) {
             ContactMeasurement c;
             c.foot = foot;
             c.p_body = fixed<3>(p_body, "p_body");
             c.cov = fixed<3, 3>(cov, "cov");
             if (!v_body.is_none()) c.v_body = fixed<3>(v_body, "v_body");
             c.probability = probability;
             return c;
           }),
           py::arg("foot"), py::arg("p_body"), py::arg("cov"), py::arg("v_body") = py::none(),
           py::arg("probability") = 1.0,
           "foot id (quadruped: 0 FL, 1 FR, 2 RL, 3 RR); p_body the foot in the body (IMU) frame "
           "[m]; cov its 3x3 covariance [m^2]; v_body its velocity relative to the body [m/s] "
           "(optional); probability p_c that it is on the ground (57.6)")
      .def_readonly("foot", &ContactMeasurement::foot)
      .def_property_readonly("p_body",
                             [](const ContactMeasurement& c) { return toArray(c.p_body); })
      .def_property_readonly("cov", [](const ContactMeasurement& c) { return toArray(c.cov); });

  py::class_<Settings>(
      m, "Settings",
      "The settings file of `legkit config` (estimation/settings.hpp): estimators, "
      "noise, priors, limits, front end, contact pipeline, robot")
      .def_readonly("estimators", &Settings::estimators,
                    "the estimators `legkit run` runs (empty: every one)")
      .def_property_readonly(
          "contact", [](const Settings& s) { return s.pipeline.contact; },
          "the contact source: a detector's name or 'truth'")
      .def("yaml", &settingsYaml, "The settings as the YAML `legkit config --print` writes")
      .def(
          "updated",
          [](const Settings& s, const std::string& text, const std::string& name) {
            return settingsFromYaml(text, name, s);
          },
          py::arg("text"), py::arg("name") = "<yaml>",
          "New settings: these with the keys of the YAML `text` replaced (the others kept), "
          "e.g. s.updated('contact: {settle_time: 0}'); errors name `name`, the line and the key");
  m.def("default_settings", &defaultSettings, "The kit's defaults (config/legkit.yaml)");
  m.def("load_settings", &loadSettings, py::arg("path"),
        "Reads a settings file; ValueError naming the file, line and key for a bad one");
  m.def(
      "settings_from_yaml",
      [](const std::string& text, const std::string& name) { return settingsFromYaml(text, name); },
      py::arg("text"), py::arg("name") = "<yaml>",
      "Settings from YAML text on the kit's defaults; `name` stands for the file in messages");

  py::class_<Estimator>(m, "Estimator",
                        "One estimator behind the kit's interface (estimation/estimator.hpp)")
      .def_property_readonly("name", &Estimator::name)
      .def("reset", &Estimator::reset, py::arg("x0"),
           "Starts over from x0 with the prior covariance; health is cleared")
      .def(
          "step",
          [](Estimator& e, double t, double dt, py::handle gyro, py::handle acc,
             const std::vector<ContactMeasurement>& contacts,
             const std::optional<std::vector<double>>& normal_force) {
            e.step(stepInput(t, dt, gyro, acc, contacts, normal_force));
          },
          py::arg("t"), py::arg("dt"), py::arg("gyro"), py::arg("acc"),
          py::arg("contacts") = std::vector<ContactMeasurement>{},
          py::arg("normal_force") = py::none(),
          "Consumes one IMU sample: t [s], dt since the previous one [s] (the first after reset "
          "is never integrated), gyro w_m [rad/s] and acc a_m [m/s^2] in the body frame, the "
          "stance feet. ValueError (the C++ message, naming the field and time) for input no "
          "caller can mean: NaN, dt < 0, a foot twice, a covariance not SPD")
      .def("estimate", &Estimator::estimate)
      .def(
          "covariance",
          [](const Estimator& e) -> py::object {
            const std::optional<BaseCovariance> P = e.covariance();
            if (!P) return py::none();
            return py::make_tuple(toArray(P->P), P->has_attitude);
          },
          "(P, has_attitude): the 9x9 covariance of (dtheta world, dv, dp), or None for an "
          "estimator without one; without attitude only rows/columns 3..8 mean something")
      .def(
          "health", [](const Estimator& e) { return faults(e.health()); },
          "The non-zero fault counts since the last reset, by name");

  py::class_<StateEstimator>(
      m, "StateEstimator",
      "The estimator manager of 57.11 (estimation/state_estimator.hpp): contact detection, leg "
      "odometry and a filter behind the one call a control loop makes per IMU sample, configured "
      "from the settings, with a ring buffer of past states for a controller's queries")
      .def(py::init<const Settings&, std::size_t, double>(), py::arg("settings"),
           py::arg("history") = StateEstimator::kDefaultHistory,
           py::arg("imu_period") = StateEstimator::kDefaultImuPeriod)
      .def(
          "update",
          [](StateEstimator& s, double t, py::handle gyro, py::handle acc, py::handle q,
             py::handle dq, py::handle force, py::handle contact, bool joints_valid) {
            const ImuSample imu{t, fixed<3>(gyro, "gyro"), fixed<3>(acc, "acc")};
            return outputDict(
                s.update(imu, jointSample(q, dq, joints_valid), forceSample(force, contact)));
          },
          py::arg("t"), py::arg("gyro"), py::arg("acc"), py::arg("q"), py::arg("dq"),
          py::arg("force") = py::none(), py::arg("contact") = py::none(),
          py::arg("joints_valid") = true,
          "One control-loop tick: t [s] strictly increasing, gyro [rad/s] and acc [m/s^2] in the "
          "IMU frame, joint angles q [rad] and rates dq [rad/s] (the robot's joint count), normal "
          "forces per foot [N] (None: no force sensor) and the robot's own contact flags (read "
          "with contact source 'truth'). Returns {'x', 'P' (9x9 or None), 'contact', "
          "'probability', 'health', 'initialised', 'initialising', 'start', 'alarms', "
          "'uncertain'}. ValueError (nothing changes) for a time not after the last, a NaN in a "
          "valid sample, a wrong joint count")
      .def(
          "state_at",
          [](const StateEstimator& s, double t, bool nearest) {
            const StateQuery r = s.stateAt(t, nearest);
            return py::make_tuple(r.x, r.age, r.interpolated);
          },
          py::arg("t"), py::arg("nearest") = false,
          "(x, age [s], interpolated): the state at a controller's time t from the buffer")
      .def("reset", py::overload_cast<>(&StateEstimator::reset), "Starts over")
      .def("reset", py::overload_cast<const EstimateSample&>(&StateEstimator::reset), py::arg("x0"),
           "Starts over from a known base state at the next sample")
      .def_property_readonly("estimator", &StateEstimator::estimatorName)
      .def_property_readonly("contact_source", &StateEstimator::contactSource)
      .def_property_readonly("num_joints", &StateEstimator::numJoints)
      .def_property_readonly("num_feet", &StateEstimator::numFeet);

  py::class_<slip::SlipDetector>(
      m, "SlipDetector",
      "The slip check of 57.7 (estimation/slip/slip_detector.hpp): each stance foot's velocity "
      "residual r_i = v_leg,i - v_hat against its covariance (d2_i = r^T S^-1 r > chi2_3(alpha) at "
      "confirm_samples consecutive checks: slipping), the multi-foot outlier, and the all-feet "
      "test of the legs' common velocity against the IMU")
      .def(py::init([](double alpha, double foot_velocity_sigma, int confirm_samples) {
             slip::SlipParams params;
             params.alpha = alpha;
             params.foot_velocity_sigma = foot_velocity_sigma;
             params.confirm_samples = confirm_samples;
             return slip::SlipDetector(params);
           }),
           py::arg("alpha") = slip::SlipParams{}.alpha,
           py::arg("foot_velocity_sigma") = slip::SlipParams{}.foot_velocity_sigma,
           py::arg("confirm_samples") = slip::SlipParams{}.confirm_samples,
           "alpha the chi-square test level; foot_velocity_sigma the noise of a foot's velocity "
           "relative to the body per axis [m/s]; confirm_samples the checks in a row")
      .def("reset", &slip::SlipDetector::reset)
      .def_property_readonly("threshold", &slip::SlipDetector::threshold, "chi2_3(alpha)")
      .def(
          "check",
          [](slip::SlipDetector& d, double t, double dt, py::handle gyro, py::handle acc,
             const std::vector<ContactMeasurement>& contacts, const EstimateSample& x, py::handle P,
             bool has_attitude) {
            const StepInput in = stepInput(t, dt, gyro, acc, contacts, std::nullopt);
            const slip::SlipReport r =
                P.is_none() ? d.check(in, x)
                            : d.check(in, x, BaseCovariance{fixed<9, 9>(P, "P"), has_attitude});
            py::list feet;
            for (int k = 0; k < r.num_feet; ++k) {
              const slip::FootSlip& f = r.feet[k];
              feet.append(py::dict(py::arg("foot") = f.foot, py::arg("d2") = f.d2,
                                   py::arg("exceeds") = f.exceeds, py::arg("slipping") = f.slipping,
                                   py::arg("residual") = toArray(f.residual),
                                   py::arg("v_leg") = toArray(f.v_leg)));
            }
            return py::dict(py::arg("feet") = feet, py::arg("all_slipping") = r.all_slipping,
                            py::arg("outlier") = r.outlier,
                            py::arg("imu_disagrees") = r.imu_disagrees,
                            py::arg("common_d2") = r.common_d2);
          },
          py::arg("t"), py::arg("dt"), py::arg("gyro"), py::arg("acc"), py::arg("contacts"),
          py::arg("x"), py::arg("P") = py::none(), py::arg("has_attitude") = true,
          "One sample's check: the stance feet (those with v_body are checked) against the "
          "estimate x of the previous step and its 9x9 covariance P (None: an estimator without "
          "one). Returns {'feet': [{'foot', 'd2', 'exceeds', 'slipping', 'residual', 'v_leg'}], "
          "'all_slipping', 'outlier' (-1: none), 'imu_disagrees', 'common_d2'}");

  m.def("names", &estimatorNames, "Every estimator, in the order of the chapter");
  m.def(
      "make",
      [](const std::string& name, const std::optional<Settings>& settings) {
        return makeEstimator(name, settings ? *settings : defaultSettings());
      },
      py::arg("name"), py::arg("settings") = py::none(),
      "A new estimator by name (names()) with the settings' parameters (default: the kit's)");

  m.def(
      "run",
      [](const io::Log& log, const std::optional<Settings>& given,
         const std::optional<std::string>& contact,
         const std::optional<std::vector<std::string>>& names,
         const std::optional<EstimateSample>& x0, const std::optional<contact::GaitSchedule>& gait,
         const std::optional<contact::LogisticModel>& model, unsigned training_seed) {
        Settings settings = given ? *given : defaultSettings();
        if (contact) settings.pipeline.contact = *contact;
        contact::DetectorContext
            context;  // forces: the settings' and the robot's (runWithSettings)
        context.gait = gait;
        context.logistic = model;
        const std::vector<std::string> which = names                         ? *names
                                               : settings.estimators.empty() ? estimatorNames()
                                                                             : settings.estimators;
        std::vector<eval::RunResult> runs;
        {
          py::gil_scoped_release release;
          if (settings.pipeline.contact == "probabilistic" && !context.logistic) {
            context.logistic = eval::trainContactModel(training_seed);
          }
          for (const std::string& name : which) {
            runs.push_back(eval::runWithSettings(log, settings, name, context, x0));
          }
        }
        py::dict out;
        for (const eval::RunResult& r : runs)
          out[r.name.c_str()] = runArrays(r, log.layout.num_feet);
        return out;
      },
      py::arg("log"), py::arg("settings") = py::none(), py::arg("contact") = py::none(),
      py::arg("estimators") = py::none(), py::arg("x0") = py::none(), py::arg("gait") = py::none(),
      py::arg("model") = py::none(), py::arg("training_seed") = 1,
      "Runs a whole log in C++, as `legkit run --log F --config S` does: the settings' front "
      "end, contact pipeline (`contact` overrides its source) and estimators (`estimators` "
      "overrides the list), from x0 (default: the log's first true state, or at rest). `gait`: "
      "the robot's planned gait (legkit.contact.GaitSchedule; gait-clock needs one); `model`: "
      "the LogisticModel of 'probabilistic' (default: the kit's, trained from training_seed as "
      "`legkit run` does). Returns {name: "
      "{'t', 'q' (N,4 w x y z), 'p', 'v' (N,3), 'sigma' (N,9: theta, v, p), 'nees', 'nees_dof', "
      "'contacts' (N, feet), 'slip' (per row: feet 'checked', 'slipping', 'all_slipping', the "
      "'outlier' foot or -1, and the 'reaction'), 'health', 'healthy', 'failure', "
      "'us_per_step', 'start' (the still start's line, or None when the gyro bias started at "
      "zero)}}. "
      "The GIL is "
      "released while it runs.");
}

}  // namespace legkit::python
