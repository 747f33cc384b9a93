#include "estimation/contact/logistic_training.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::contact {

namespace {

Eigen::Vector3d raw(const ContactFeatures& x) {
  return {x.force, x.foot_speed, x.phase};
}

constexpr const char* kFeatureName[3] = {"force", "foot_speed", "phase"};

// log(1 + e^z) without overflow.
double softplus(double z) {
  return z > 0.0 ? z + std::log1p(std::exp(-z)) : std::log1p(std::exp(z));
}

}  // namespace

LogisticModel trainLogistic(const std::vector<ContactFeatures>& samples,
                            const std::vector<bool>& labels, const TrainingOptions& options) {
  if (samples.empty()) throw std::invalid_argument("trainLogistic: no samples");
  if (labels.size() != samples.size())
    throw std::invalid_argument("trainLogistic: " + std::to_string(labels.size()) + " labels for " +
                                std::to_string(samples.size()) + " samples");
  if (!(options.l2 >= 0.0) || options.max_iterations < 1 || !(options.tolerance > 0.0))
    throw std::invalid_argument(
        "trainLogistic: options need l2 >= 0, max_iterations >= 1, tolerance > 0");
  const bool use[3] = {options.use_force, options.use_foot_speed, options.use_phase};
  if (!use[0] && !use[1] && !use[2])
    throw std::invalid_argument("trainLogistic: no feature in use");

  // Feature scaling: mean and standard deviation of each used feature over the set.
  const double n = static_cast<double>(samples.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t positives = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Eigen::Vector3d x = raw(samples[k]);
    for (int i = 0; i < 3; ++i)
      if (use[i] && !std::isfinite(x[i]))
        throw std::invalid_argument("trainLogistic: feature " + std::string(kFeatureName[i]) +
                                    " of sample " + std::to_string(k) + " is not finite");
    sum += x;
    positives += labels[k] ? 1 : 0;
  }
  if (positives == 0 || positives == samples.size())
    throw std::invalid_argument(std::string("trainLogistic: every label is ") +
                                (positives == 0 ? "'no contact'" : "'contact'") +
                                ": nothing to separate");
  // Two passes (mean, then the squared deviations): no cancellation for a feature far from 0.
  const Eigen::Vector3d mean = sum / n;
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  for (const ContactFeatures& f : samples) sq += (raw(f) - mean).cwiseAbs2();
  LogisticModel model;
  bool active[3];
  for (int i = 0; i < 3; ++i) {
    const double var = sq[i] / n;
    active[i] = use[i] && var > 1e-12 * (1.0 + mean[i] * mean[i]);
    model.mean[i] = active[i] ? mean[i] : 0.0;
    model.scale[i] = active[i] ? std::sqrt(var) : 1.0;
  }

  // Newton / IRLS on w = (b, w_F, w_v, w_phi); inactive features keep weight 0 (their row and
  // column of the Hessian are replaced by the identity, their gradient by 0).
  Eigen::Vector4d w = Eigen::Vector4d::Zero();
  w[0] = std::log(static_cast<double>(positives) / (n - static_cast<double>(positives)));
  Eigen::Vector4d penalty(0.0, options.l2, options.l2, options.l2);
  // The scaled sample k, (1, x_scaled), inactive features 0.
  const auto features = [&](std::size_t k) {
    const Eigen::Vector3d x = raw(samples[k]);
    Eigen::Vector4d phi(1.0, 0.0, 0.0, 0.0);
    for (int i = 0; i < 3; ++i)
      if (active[i]) phi[i + 1] = (x[i] - model.mean[i]) / model.scale[i];
    return phi;
  };
  // L(w): sum_n softplus(z_n) - y_n z_n, plus the penalty.
  const auto loss = [&](const Eigen::Vector4d& v) {
    double l = 0.5 * penalty.dot(v.cwiseAbs2());
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const double z = v.dot(features(k));
      l += softplus(z) - (labels[k] ? z : 0.0);
    }
    return l;
  };
  double largest = 0.0;  // the last step's largest component
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
    Eigen::Vector4d g = Eigen::Vector4d::Zero();
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const Eigen::Vector4d phi = features(k);
      const double p = 1.0 / (1.0 + std::exp(-w.dot(phi)));
      g += (p - (labels[k] ? 1.0 : 0.0)) * phi;
      H.selfadjointView<Eigen::Lower>().rankUpdate(phi, std::max(p * (1.0 - p), 1e-12));
    }
    H = H.selfadjointView<Eigen::Lower>();
    H.diagonal() += penalty;
    g += penalty.cwiseProduct(w);
    for (int i = 0; i < 3; ++i)
      if (!active[i]) {
        H.row(i + 1).setZero();
        H.col(i + 1).setZero();
        H(i + 1, i + 1) = 1.0;
        g[i + 1] = 0.0;
      }
    Eigen::Vector4d step = H.ldlt().solve(g);
    if (!step.allFinite())
      throw std::invalid_argument("trainLogistic: the Newton step is not finite");
    // Armijo backtracking: L(w - t step) <= L(w) - c t g.step (g.step > 0: H is SPD).
    const double l0 = loss(w), slope = g.dot(step);
    while (loss(w - step) > l0 - 1e-4 * slope && step.cwiseAbs().maxCoeff() >= options.tolerance)
      step *= 0.5;
    w -= step;
    largest = step.cwiseAbs().maxCoeff();
    if (largest < options.tolerance) {
      model.w = w;
      return model;
    }
  }
  throw std::runtime_error(
      "trainLogistic: no convergence in " + std::to_string(options.max_iterations) +
      " Newton steps (the last step's largest component " + std::to_string(largest) + ")");
}
}  // namespace legkit::contact
