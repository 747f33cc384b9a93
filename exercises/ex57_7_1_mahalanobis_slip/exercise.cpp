// Your solution to exercise 57.7.1. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_7_1.hpp"

namespace ex57_7_1 {

double mahalanobisSquared(const FootResidual& /*foot*/, const Matrix9& /*P*/) {
  throw legkit::NotImplemented("mahalanobisSquared");
}

double chiSquare3Quantile(double /*alpha*/) {
  throw legkit::NotImplemented("chiSquare3Quantile");
}

SlipVerdict detectSlip(const FootResidual* /*feet*/, int /*n*/, const Matrix9& /*P*/,
                       double /*alpha*/) {
  throw legkit::NotImplemented("detectSlip");
}

}  // namespace ex57_7_1
