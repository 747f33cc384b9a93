// Linked into every exercise program: after a test case that failed, say what to read. The test
// case's tags name the exercise ([ex57.2.1]) and, optionally, the README hint that helps ([hint
// 2]); the chapter section file and the exercise folder are found under the source tree.
#define CATCH_CONFIG_EXTERNAL_INTERFACES  // Catch's listener base class
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

// The first entry of `dir` whose name starts with `prefix`, as a path relative to the source tree.
std::string findUnder(const std::string& dir, const std::string& prefix) {
  const fs::path root(LEGKIT_SOURCE_DIR);
  std::error_code ec;
  std::string best;
  for (const auto& entry : fs::directory_iterator(root / dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && (best.empty() || name < best)) best = name;
  }
  return best.empty() ? std::string() : dir + "/" + best;
}

class ExerciseHintListener : public Catch::TestEventListenerBase {
 public:
  using TestEventListenerBase::TestEventListenerBase;

  void testCaseEnded(const Catch::TestCaseStats& stats) override {
    if (stats.totals.assertions.failed == 0) return;
    std::string id, hint;  // "57.2.1", "2"
    for (const std::string& tag : stats.testInfo.tags) {
      if (tag.rfind("ex", 0) == 0) id = tag.substr(2);
      if (tag.rfind("hint ", 0) == 0) hint = tag.substr(5);
    }
    if (id.empty()) return;
    const std::string section = id.substr(0, id.rfind('.'));  // 57.2.1 -> 57.2
    std::string folder_prefix = "ex" + id + "_";
    for (char& c : folder_prefix)
      if (c == '.') c = '_';
    const std::string folder = findUnder("exercises", folder_prefix);
    // 57.X spans sections: its README names the chapters to read.
    const bool cross_section = section.find('.') == std::string::npos;
    const std::string chapter = cross_section ? "" : findUnder("chapters", section + "-");
    stream << "Read: "
           << (cross_section
                   ? std::string("the chapters named")
                   : (chapter.empty() ? "chapter" : chapter) + " (section " + section + ")")
           << " and " << (hint.empty() ? "the hints" : "hint " + hint) << " in "
           << (folder.empty() ? "the exercise's" : folder + "/") << "README.md\n\n";
  }
};

}  // namespace

CATCH_REGISTER_LISTENER(ExerciseHintListener)
