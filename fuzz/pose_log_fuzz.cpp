// libFuzzer target for the pose-file reader (tools/fuzz-reader.sh poses builds and runs it).
//
// Whatever the bytes, readPoseLog either throws io::LogError or returns poses; nothing else may
// happen (no other exception, no crash, no sanitizer report), and a LogError's message is short
// and printable. What it accepts is what the header promises (stamps strictly increasing, every
// number finite, covariances with a finite Cholesky factor), and it survives the round trip:
// written back and read again, t, t_arrival, p, the covariance and the flag are the same and the
// attitude is within kPoseLogAttitudeRoundTrip.
#include <Eigen/Cholesky>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "estimation/fusion/pose_log.hpp"
#include "io/log_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace legkit::fusion;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<PoseMeasurement> poses;
  try {
    poses = readPoseLog(in, "fuzz.csv");
  } catch (const legkit::io::LogError& e) {
    const std::string message = e.what();
    if (message.size() > 600) std::abort();
    for (const char c : message) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
        std::abort();
    }
    return 0;
  }
  if (poses.empty()) std::abort();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const PoseMeasurement& z = poses[k];
    if (k > 0 && !(z.t > poses[k - 1].t)) std::abort();
    if (!(z.t_arrival >= z.t) || !z.p_MB.allFinite() || !z.R_MB.matrix().allFinite()) std::abort();
    const Eigen::LLT<Matrix6d> llt(z.cov);
    if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite()) std::abort();
  }
  std::stringstream file;
  writePoseLog(file, poses, {"fuzz"}, "fuzz-out.csv");  // must not throw for what was read
  const std::vector<PoseMeasurement> again = readPoseLog(file, "fuzz-out.csv");
  if (again.size() != poses.size()) std::abort();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const PoseMeasurement& a = poses[k];
    const PoseMeasurement& b = again[k];
    if (a.t != b.t || a.t_arrival != b.t_arrival || a.p_MB != b.p_MB || a.cov != b.cov ||
        a.valid != b.valid) {
      std::abort();
    }
    if ((a.R_MB.matrix() - b.R_MB.matrix()).cwiseAbs().maxCoeff() > kPoseLogAttitudeRoundTrip)
      std::abort();
  }
  return 0;
}
