#include "shard.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include "output.hpp"

namespace legkit::tools {
namespace {

// A decimal whole number of at most 5 digits, or -1.
int smallNumber(const std::string& text) {
  if (text.empty() || text.size() > 5) return -1;
  for (const char c : text) {
    if (c < '0' || c > '9') return -1;
  }
  return std::stoi(text);
}

std::string describe(const ShardInput& s) {
  return s.dir + " (shard " + s.shard.text() + ")";
}

// The first key of a and b (objects) whose values differ, for the error message.
std::string firstDifference(const nlohmann::json& a, const nlohmann::json& b) {
  for (auto it = a.begin(); it != a.end(); ++it) {
    if (!b.contains(it.key()) || b.at(it.key()) != it.value()) return it.key();
  }
  for (auto it = b.begin(); it != b.end(); ++it) {
    if (!a.contains(it.key())) return it.key();
  }
  return "";
}

}  // namespace

Shard parseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const std::string shown = "'" + text.substr(0, 40) + (text.size() > 40 ? "...'" : "'");
  if (slash == std::string::npos) {
    throw std::invalid_argument("must be i/N (shard i of N, e.g. 2/8), got " + shown);
  }
  const int i = smallNumber(text.substr(0, slash));
  const int n = smallNumber(text.substr(slash + 1));
  if (i < 0 || n < 0) {
    throw std::invalid_argument("must be i/N with whole numbers i and N, got " + shown);
  }
  if (n < 1 || n > 10000) throw std::invalid_argument("N must be in [1, 10000], got " + shown);
  if (i < 1 || i > n) throw std::invalid_argument("i must be in [1, N], got " + shown);
  return {i, n};
}

CLI::Validator shardSpec() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          parseShard(text);
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
        return "";
      },
      "i/N");
}

Block shardBlock(const Shard& shard, int total, const std::string& what) {
  if (shard.count > total) {
    throw UsageError("--shard " + shard.text() + ": only " + std::to_string(total) + " " + what +
                     ", so at most " + std::to_string(total) + " shards");
  }
  const auto at = [&](int i) {
    return static_cast<int>(static_cast<long long>(i) * total / shard.count);
  };
  return {at(shard.index - 1), at(shard.index)};
}

std::string fileDigest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  std::uint64_t hash = 14695981039346656037ull;
  for (std::istreambuf_iterator<char> it(in), end; it != end; ++it) {
    hash = (hash ^ static_cast<unsigned char>(*it)) * 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

nlohmann::json shardManifest(const std::string& kind, const nlohmann::json& options,
                             const Shard& shard, const Block& block) {
  return {{"legkit_version", LEGKIT_VERSION},
          {"kind", kind},
          {"options", options},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"block", {block.begin, block.end}}};
}

ShardInput readShard(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path path = fs::path(dir) / kShardManifest;
  std::ifstream in(path);
  if (!in) {
    throw InputError(dir + ": no " + std::string(kShardManifest) +
                     ": not a shard's output folder, or its shard has not finished");
  }
  ShardInput s{dir, {}, {}, {}};
  try {
    s.manifest = nlohmann::json::parse(in);
    const nlohmann::json& shard = s.manifest.at("shard");
    s.shard = {shard.at("index").get<int>(), shard.at("count").get<int>()};
    s.block = {s.manifest.at("block").at(0).get<int>(), s.manifest.at("block").at(1).get<int>()};
    s.manifest.at("kind").get<std::string>();
    s.manifest.at("legkit_version").get<std::string>();
    s.manifest.at("options");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not a shard manifest (" + e.what() + ")");
  }
  if (s.shard.count < 1 || s.shard.index < 1 || s.shard.index > s.shard.count) {
    throw InputError(path.string() + ": shard " + s.shard.text() + " is not i/N with 1 <= i <= N");
  }
  return s;
}

std::vector<ShardInput> checkShards(std::vector<ShardInput> shards) {
  if (shards.empty()) throw InputError("no shard folders given");
  const ShardInput& first = shards.front();
  for (const ShardInput& s : shards) {
    for (const char* key : {"kind", "legkit_version"}) {
      if (s.manifest.at(key) != first.manifest.at(key)) {
        throw InputError(std::string("shards of different runs: ") + key + " is " +
                         first.manifest.at(key).dump() + " in " + describe(first) + " but " +
                         s.manifest.at(key).dump() + " in " + describe(s) + "; nothing merged");
      }
    }
    if (s.manifest.at("options") != first.manifest.at("options")) {
      const std::string key =
          firstDifference(first.manifest.at("options"), s.manifest.at("options"));
      const auto value = [&](const ShardInput& x) {
        return x.manifest.at("options").contains(key) ? x.manifest.at("options").at(key).dump()
                                                      : std::string("(absent)");
      };
      throw InputError("shards of different runs: option '" + key + "' is " + value(first) +
                       " in " + describe(first) + " but " + value(s) + " in " + describe(s) +
                       "; nothing merged");
    }
    if (s.shard.count != first.shard.count) {
      throw InputError("shards of different splits: " + describe(first) + " and " + describe(s) +
                       "; nothing merged");
    }
  }
  const int n = first.shard.count;
  std::map<int, const ShardInput*> by_index;
  for (const ShardInput& s : shards) {
    const auto [it, added] = by_index.emplace(s.shard.index, &s);
    if (!added) {
      throw InputError("shard " + s.shard.text() + " given twice: " + it->second->dir + " and " +
                       s.dir + "; nothing merged");
    }
  }
  std::string missing;
  for (int i = 1; i <= n; ++i) {
    if (!by_index.count(i)) missing += (missing.empty() ? "" : ", ") + Shard{i, n}.text();
  }
  if (!missing.empty()) {
    throw InputError("shard " + missing + " missing (" + std::to_string(shards.size()) + " of " +
                     std::to_string(n) + " given); nothing merged");
  }
  std::vector<ShardInput> ordered;
  int next = 0;
  for (const auto& [i, s] : by_index) {
    if (s->block.begin != next || s->block.end < s->block.begin) {
      throw InputError(s->dir + ": its block [" + std::to_string(s->block.begin) + ", " +
                       std::to_string(s->block.end) + ") does not follow shard " +
                       std::to_string(i - 1) + "'s; nothing merged");
    }
    next = s->block.end;
    ordered.push_back(*s);
  }
  return ordered;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t from = 0;
  for (std::size_t comma = line.find(','); comma != std::string::npos;
       comma = line.find(',', from)) {
    fields.push_back(line.substr(from, comma - from));
    from = comma + 1;
  }
  fields.push_back(line.substr(from));
  return fields;
}

std::string exact(double value) {
  if (std::isnan(value)) return "nan";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

double parseExact(const std::string& field, const std::string& where) {
  if (field == "nan") return std::nan("");
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(field.c_str(), &end);
  if (field.empty() || end != field.c_str() + field.size() ||
      (errno == ERANGE && std::isinf(value))) {
    throw InputError(where + ": '" + field.substr(0, 40) + "' is not a number");
  }
  return value;
}

std::filesystem::path studyFolder(const std::string& given, const std::string& study,
                                  const Shard& shard) {
  if (!given.empty()) return given;
  return "legkit-out/study-" + study +
         (shard.whole()
              ? std::string()
              : "-shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count));
}

void writeStudyShard(const std::filesystem::path& dir, const std::string& study,
                     const nlohmann::json& options, const Shard& shard, const Block& block,
                     const std::function<void(std::ostream&)>& rows) {
  OutputFolder folder(dir, kShardManifest);
  folder.write(kStudyRows, rows);
  folder.writeManifest(shardManifest("study " + study, options, shard, block));
}

}  // namespace legkit::tools
