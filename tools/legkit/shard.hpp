// Sharding a study or a batch evaluation across processes or machines (`--shard i/N`), and what
// `legkit merge` checks before it combines the shards (chapters/commands.md, "Past one machine").
//
// Shard i of N takes a contiguous block of the items (Monte Carlo runs, logs): items
// [floor((i-1) M / N), floor(i M / N)) of M. An item's result depends only on its index (run j is
// seeded seed + j, a log is its file), so the shards' per-item rows, written with every bit
// (%.17g), are exactly the single-machine run's, and `legkit merge` recomputes the aggregate from
// them with the single-machine run's own code. Each shard's folder holds its manifest
// (kShardManifest): the kind of run, its options, the version, i/N and its block.
// There is no scheduler here: GNU parallel or a Slurm job array starts the shards.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace legkit::tools {

inline constexpr const char* kShardManifest = "shard.json";
// A study shard's per-run rows, beside its manifest.
inline constexpr const char* kStudyRows = "rows.csv";

struct Shard {
  int index = 1;  // i, 1-based
  int count = 1;  // N
  bool whole() const { return count == 1; }
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

// "i/N" with 1 <= i <= N <= 10000, both decimal; throws std::invalid_argument saying what is
// wrong with `text` otherwise.
Shard parseShard(const std::string& text);

// The CLI11 check of a --shard option (parseShard's message; exit 1 naming the option).
CLI::Validator shardSpec();

// Items [begin, end) of shard i/N over `total` items.
struct Block {
  int begin = 0;
  int end = 0;
};
// Throws UsageError "--shard i/N: ..." when N exceeds `total` (a shard would be empty); `what`
// names the items ("runs", "logs").
Block shardBlock(const Shard& shard, int total, const std::string& what);

// FNV-1a (64 bit) of a file's bytes as 16 hex digits, stable across machines and builds: the
// identity of a settings file in a shard's manifest. Throws InputError if it cannot be read.
std::string fileDigest(const std::string& path);

// A shard's manifest as written into its folder: kind ("study consistency", "eval"), options
// (everything that changes the result), the version, i/N and the block.
nlohmann::json shardManifest(const std::string& kind, const nlohmann::json& options,
                             const Shard& shard, const Block& block);

// A shard folder given to `legkit merge`: its manifest, read and checked.
struct ShardInput {
  std::string dir;
  nlohmann::json manifest;
  Shard shard;
  Block block;
};
// Reads DIR/shard.json; InputError naming the folder when it is missing (the shard has not
// finished) or not a shard's manifest.
ShardInput readShard(const std::string& dir);

// Orders the shards 1..N after checking that they are one run's: the same kind, options and
// version, the same N, each i exactly once and none missing, blocks that tile 0..total. Throws
// InputError naming the folders and what differs.
std::vector<ShardInput> checkShards(std::vector<ShardInput> shards);

// A study's folder: `given` (--out), or legkit-out/study-<study>, with -shard-<i>-of-<N> for a
// shard (shards on one machine must not share a folder).
std::filesystem::path studyFolder(const std::string& given, const std::string& study,
                                  const Shard& shard);

// Writes a study shard into `dir`: its per-item rows (kStudyRows, by `rows`) and its manifest
// (kind "study <study>", `options`, i/N, the block). The caller says on its output what it holds.
void writeStudyShard(const std::filesystem::path& dir, const std::string& study,
                     const nlohmann::json& options, const Shard& shard, const Block& block,
                     const std::function<void(std::ostream&)>& rows);

// The comma-separated fields of one row of a shard's rows file (an empty last field kept).
std::vector<std::string> splitCsv(const std::string& line);

// Full-precision numbers for per-item rows: %.17g (NaN as "nan"), read back bit for bit.
std::string exact(double value);
// Parses one exact() field; throws InputError "<where>: ..." unless it is a whole number.
double parseExact(const std::string& field, const std::string& where);

}  // namespace legkit::tools
