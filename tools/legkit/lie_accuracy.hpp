// `legkit lie-accuracy`: how accurately lie/ evaluates the angle coefficients that cancel, next
// to the textbook closed forms, measured against a long-double reference. It makes the data of
// the figure chapters/figures/lie-coefficient-accuracy.png (tools/plots/lie_accuracy.py).
#pragma once

#include <ostream>
#include <string>

namespace legkit::tools {

// For theta on a log grid from 1e-10 to pi, computes the relative error of
//   G_3 = (theta - sin theta) / theta^3,
//   G_4 = (theta^2/2 + cos theta - 1) / theta^4,
//   C   = (G_4 - 3 G_5) / 2 = (2 theta - 3 sin theta + theta cos theta) / (2 theta^5)
//         (the coefficient of the SE(3) coupling block Q, see lie/sek3.hpp),
// each once from the closed form written naively in double and once from lie::AngleSeries.
// Prints a summary to `out`; when csvPath is not empty, also writes one row per theta there,
// preceded by '#' comment lines giving lie's Taylor switch points. Returns 0, or 2 when the file
// cannot be written.
int lieAccuracy(std::ostream& out, const std::string& csvPath, int points);

}  // namespace legkit::tools
