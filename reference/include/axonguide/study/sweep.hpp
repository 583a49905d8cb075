#pragma once
// Parameter sweeps (docs/methods.md §12.2). A sweep is a base scene, parameters (scene key
// paths and their values) and seeds. Member m is a pure function of (sweep, m): its scene
// is the base with the point's values and the seed applied, and it is run single-file with
// no outputs but its record. Members run in any order, on any thread or (later) any MPI
// rank; the gathered files are written in member order, so their bytes never depend on
// the schedule.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/engine/run.hpp"

namespace axg::sweep {

struct Parameter {
  std::string name;               // column name (the first key unless given)
  std::vector<std::string> keys;  // dotted paths; "*" stands for every element of an array
  std::vector<nlohmann::json> values;  // with cases: their labels
  // "cases": {"label": {"key": value, ...}, ...}: each value sets several keys (a named
  // condition such as a control); empty for a plain parameter.
  std::vector<nlohmann::json> cases;
};

struct Spec {
  nlohmann::json base;  // the base scene, as written (indices follow the file's order)
  std::string base_origin;
  std::vector<Parameter> parameters;
  bool zip = false;  // false: the grid (first parameter slowest); true: the i-th value of each
  std::vector<std::uint64_t> seeds;
  bool write_runs = false;  // each member also writes its full run folder under members/
};

// Parses a sweep file; a relative "scene" path is read from the sweep file's folder.
// InputError names the key on bad input.
Spec load_spec(const std::string& path);
Spec parse_spec(const nlohmann::json& j, const std::string& origin, const std::filesystem::path& folder);

std::size_t point_count(const Spec& spec);
std::size_t member_count(const Spec& spec);
// The values of point p, one per parameter.
std::vector<nlohmann::json> point_values(const Spec& spec, std::size_t point);
// The scene JSON of member m (base, point values, seed); parse it with parse_scene.
nlohmann::json member_scene_json(const Spec& spec, std::size_t member);

// What one member produced.
struct MemberResult {
  std::size_t member = 0;
  bool ok = false;
  bool skipped = false;  // a verified record from an earlier run was reused
  int exit_code = 0;
  std::string message;
  std::vector<std::pair<std::string, double>> metrics;
  std::string connections_sha256;
  std::string scene_sha256;
};

// Runs member m in memory and measures it; never throws (failures are recorded).
// With a run_dir, the member's full run folder is written there (manifest naming backend).
MemberResult run_member(const Spec& spec, std::size_t member, const RunOptions& options,
                        const std::filesystem::path& run_dir = {}, const std::string& backend = "reference");

// Runs the members `pending` (in any order, anywhere) and hands each one's result to
// `record`, one call at a time. The default is a TBB loop on Options::threads threads; the
// MPI build hands the members to ranks (distributed/mpi_sweep.cpp).
using Record = std::function<void(MemberResult)>;
using Executor = std::function<void(const std::vector<std::size_t>& pending, const Record& record)>;

struct Options {
  int threads = 0;
  RunOptions run;  // the backend's engine
  std::string backend = "reference";
  Executor execute;  // empty: the TBB loop
  // Called after each member completes (from worker threads, serialised).
  std::function<void(std::size_t done, std::size_t total, std::size_t failed, std::size_t skipped)> on_member;
};

struct Outcome {
  std::vector<MemberResult> members;
  std::size_t failed = 0, skipped = 0;
};

// Runs every member not already recorded and verified in dir/members/, then writes
// dir/sweep.csv, dir/summary.csv and dir/sweep.json (the canonical sweep).
Outcome run(const Spec& spec, const std::filesystem::path& dir, const Options& options);

// A member's record (dir/members/mNNNNNNN.json without its record_sha256), and the result
// it holds: the two round-trip exactly (metrics as shortest round-trip doubles, NaN as
// null), which is how results cross between MPI ranks.
nlohmann::json record_json(const MemberResult& r, std::uint64_t seed);
MemberResult result_from_record(const nlohmann::json& record);

// The record file of a member, and whether a record is complete and verified for it.
std::filesystem::path record_path(const std::filesystem::path& dir, std::size_t member);
std::optional<MemberResult> read_verified_record(const Spec& spec, const std::filesystem::path& dir,
                                                 std::size_t member);

// Runs every member of every spec in memory (no files) in one parallel loop, for callers
// that evaluate many sweeps at once (the fit, the validation); results are flattened in
// (spec, member) order and do not depend on the thread count.
std::vector<MemberResult> run_in_memory(const std::vector<Spec>& specs, int threads, const RunOptions& options);

// A member's metric by name (NaN when the member failed).
double metric(const MemberResult& r, const std::string& name);

// Mean and standard error of the mean of xs (NaN entries ignored); n < 2: se NaN.
struct MeanSe {
  std::size_t n = 0;
  double mean, se;
};
MeanSe mean_se(const std::vector<double>& xs);

// Two-sided 95 % Student-t interval of the mean of xs (NaN entries ignored); n < 2: NaN.
struct MeanCi {
  std::size_t n = 0;
  double mean, low, high;
};
MeanCi mean_ci(const std::vector<double>& xs);

}  // namespace axg::sweep
