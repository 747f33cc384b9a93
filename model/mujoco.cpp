#include "model/mujoco.hpp"

#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace legkit::model {
namespace {

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

// MuJoCo's default warning handler also appends to MUJOCO_LOG.TXT in the working directory. The
// kit reads the warning counters of mjData instead (sim/physics_simulator.cpp turns them into a
// failed run), so a warning only goes to stderr and leaves no file behind.
void warnToStderr(const char* message) {
  std::fprintf(stderr, "MuJoCo warning: %s\n", message);
}

}  // namespace

MjModelPtr loadMjcf(const std::string& xml, const std::string& name) {
  mju_user_warning = warnToStderr;
  const std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("loadMjcf: cannot create the virtual file '" + name + "'");
  }
  const int file = mj_findFileVFS(vfs.get(), name.c_str());
  if (file < 0) throw std::runtime_error("loadMjcf: virtual file '" + name + "' not found");
  std::memcpy(vfs->filedata[file], xml.data(), xml.size());
  char error[1000] = "";
  MjModelPtr m(mj_loadXML(name.c_str(), vfs.get(), error, sizeof(error)));
  if (!m) throw std::runtime_error("loadMjcf: MuJoCo rejected '" + name + "': " + error);
  return m;
}

MjDataPtr makeData(const mjModel& m) {
  MjDataPtr d(mj_makeData(&m));
  if (!d) throw std::runtime_error("makeData: MuJoCo could not allocate mjData");
  return d;
}

}  // namespace legkit::model
