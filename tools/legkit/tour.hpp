// `legkit tour`: a short, printed walk through the identities lie/ guarantees, with timings.
#pragma once

#include <ostream>

namespace legkit::tools {

// Prints each identity with the residual measured on random elements, and the time per call of
// the basic operations. Returns 0 when every residual is below its tolerance, 1 otherwise.
int lieTour(std::ostream& out, unsigned seed);

}  // namespace legkit::tools
