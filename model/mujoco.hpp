// Loading the kit's MJCF into MuJoCo (Debian's libmujoco-dev 2.2.2) with owning handles. MuJoCo
// 2.2.2 cannot parse MJCF from a string, only from a file: the string is put into a virtual file
// system (mjVFS, ~2 MB, so it lives on the heap) under `name` and loaded from there.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

namespace legkit::model {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// Compiles an MJCF document (e.g. quadrupedMjcf()). Also routes MuJoCo's warnings to stderr
// (instead of its default MUJOCO_LOG.TXT in the working directory). Throws std::runtime_error
// carrying MuJoCo's own message when the XML does not parse or the model does not compile.
MjModelPtr loadMjcf(const std::string& xml, const std::string& name = "legkit.xml");

// Fresh simulation data for m (at qpos0). Throws std::runtime_error when MuJoCo cannot allocate it.
MjDataPtr makeData(const mjModel& m);

}  // namespace legkit::model
