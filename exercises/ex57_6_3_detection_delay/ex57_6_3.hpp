// Exercise 57.6.3: what a contact detector that is 10 ms late costs the linear KF, measured.
#pragma once

#include "io/log.hpp"

namespace ex57_6_3 {

// How late a detector reports each edge of a foot's contact, in log rows (1 ms each at 1 kHz).
struct DetectionDelay {
  int touchdown = 10;  // the flag rises this many rows after the foot lands
  int liftoff = 10;    // the flag falls this many rows after the foot lifts off
};

// The log as a late detector would have flagged it: per foot (layout.num_feet of them), the
// detected flag starts as the log's flag at row 0 and takes a new value at row k + delay when the
// log's flag changed at row k and has kept its new value over rows k .. k + delay (touchdown delay
// for a rise, lift-off delay for a fall). A stance or swing phase shorter than the delay is never
// reported. Only the contact flags change; every other column is the log's. Throws
// std::invalid_argument for a negative delay or a log without contact flags.
legkit::io::Log delayContacts(const legkit::io::Log& log, const DetectionDelay& delay);

// The kit's linear KF (legkit::linear_kf::LinearKf, default parameters) over the log through a
// legkit::LogFrontend (default noise), reset to the log's ground truth at row 0 (pose and
// velocity): the RMS over all rows of |p_hat - p| [m]. Throws std::invalid_argument for a log
// without ground truth.
double positionRmse(const legkit::io::Log& log);

struct DelayCost {
  double on_time = 0.0;   // positionRmse of the log as it is (the true contacts) [m]
  double delayed = 0.0;   // positionRmse of delayContacts(log, delay) [m]
  double increase = 0.0;  // delayed - on_time [m]
};
DelayCost delayCost(const legkit::io::Log& log, const DetectionDelay& delay);

}  // namespace ex57_6_3
