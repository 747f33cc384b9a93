// Reference solution of exercise 57.6.2.
#include <Eigen/Cholesky>
#include <cmath>

#include "ex57_6_2.hpp"

namespace ex57_6_2 {

// Gradient g = X^T (p - y) + l2 I' w and Hessian H = X^T W X + l2 I', accumulated sample by
// sample; the step solves H dw = g (H is positive definite for l2 > 0 or full-rank X).
Eigen::Vector4d newtonStep(const Eigen::Vector4d& w, const std::vector<Eigen::Vector4d>& x,
                           const std::vector<bool>& y, double l2) {
  const Eigen::Vector4d penalty(0.0, l2, l2, l2);
  Eigen::Matrix4d H = penalty.asDiagonal();
  Eigen::Vector4d g = penalty.cwiseProduct(w);
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double p = 1.0 / (1.0 + std::exp(-w.dot(x[n])));
    g += (p - (y[n] ? 1.0 : 0.0)) * x[n];
    H += p * (1.0 - p) * x[n] * x[n].transpose();
  }
  return w - H.ldlt().solve(g);
}

LogisticModel trainContactProbability(const std::vector<ContactFeatures>& samples,
                                      const std::vector<bool>& labels, double l2) {
  const double n = static_cast<double>(samples.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
  double positives = 0.0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Eigen::Vector3d f(samples[k].force, samples[k].foot_speed, samples[k].phase);
    sum += f;
    sum_sq += f.cwiseProduct(f);
    positives += labels[k] ? 1.0 : 0.0;
  }
  LogisticModel model;
  model.mean = sum / n;
  model.scale = (sum_sq / n - model.mean.cwiseProduct(model.mean)).cwiseSqrt();
  std::vector<Eigen::Vector4d> x(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Eigen::Vector3d f(samples[k].force, samples[k].foot_speed, samples[k].phase);
    x[k] << 1.0, (f - model.mean).cwiseQuotient(model.scale);
  }
  Eigen::Vector4d w(std::log(positives / (n - positives)), 0.0, 0.0, 0.0);
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector4d next = newtonStep(w, x, labels, l2);
    const double step = (next - w).cwiseAbs().maxCoeff();
    w = next;
    if (step < 1e-10) break;
  }
  model.w = w;
  return model;
}

}  // namespace ex57_6_2
