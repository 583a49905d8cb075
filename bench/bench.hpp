#pragma once
// Benchmarks of `axonguide bench`. Each returns rows of measurements; the command
// prints them as a table or JSON. Timings are wall-clock medians of repeated runs.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/engine/run.hpp"

namespace axg::bench {

struct Row {
  std::string group;    // e.g. "samplers"
  std::string name;     // what was measured
  std::string impl;     // ours / peer name
  int threads = 1;
  double size = 0;      // problem size (points, neurons, vertices...)
  double seconds = 0;   // median wall time
  double rate = 0;      // work units per second
  std::string unit;     // work unit of `rate`
  double ratio = 0;     // rate relative to the peer named in `baseline` (0: none)
  std::string baseline;
  std::string note;
  // The run failed (no figure is reported: seconds, rate and ratio are 0); `note` says why.
  // The command then exits 3.
  bool failed = false;
};

// One line of the table `axonguide bench` prints. A failed or skipped row has no figure:
// only what was attempted and the note saying why.
std::string format_row(const Row& r);

// The row of a measurement that failed: no figure, the reason in the note.
Row failed_row(std::string group, std::string name, std::string impl, int threads, double size, std::string unit,
               std::string why);

struct Options {
  bool quick = false;
  int max_threads = 0;         // 0: all hardware threads
  EngineFactory make_engine;   // empty: reference
  std::string backend = "reference";
  std::function<void(const Row&)> on_row;  // progress (each row as it is measured)
};

std::vector<Row> samplers(const Options& o);
std::vector<Row> growth(const Options& o);
std::vector<Row> bfs(const Options& o);
std::vector<Row> particles(const Options& o);
std::vector<Row> grid(const Options& o);
// Arbours: 10^4 neurons of the culture with arbours twice the data's 5-day size (10^3 quick).
std::vector<Row> arbours(const Options& o);
Scene arbour_benchmark_scene(std::uint64_t neurons);
// Synapses: the same culture with apposition detection, end to end at 10^4 and 10^5 neurons
// (peak memory), and detection alone at three sizes of one density (O(segments)).
std::vector<Row> synapses(const Options& o);

// Median wall seconds of `repeats` calls of fn (at least one; more while under budget).
double time_median(const std::function<void()>& fn, int repeats = 5, double budget_seconds = 2.0);

// A peer and ours timed alternately, round after round, so that drift in the machine's
// speed (this VM's varies by tens of percent) hits both alike. Medians of each and of
// the per-round ratio peer_time / our_time.
struct Paired {
  double peer_seconds, our_seconds, speedup;
};
Paired time_paired(const std::function<void()>& peer, const std::function<void()>& ours, int rounds = 9);

// The report's direct-guidance density: 100 neurons in a ball of radius 2.5.
Scene paper_direct_scene(std::uint64_t neurons);

// Runs `axonguide run` on a scene in a child process (so that its peak memory is its
// own) and returns wall time, exit status (-1: not started or killed) and peak memory
// from its manifest. A run that did not exit 0 is a failed row, never a figure.
struct ChildRun {
  nlohmann::json manifest;  // the child's manifest (null when it wrote none)
  double seconds = 0;
  double peak_bytes = 0;
  double output_seconds = 0;  // the manifest's "output" phase (writing every file)
  int status = -1;
};
ChildRun run_child(const Scene& scene, int threads, const std::string& backend);

// The report's cue setting (Table 5): radius 2.5 for every size, soma radius scaled to
// keep packing fraction 0.1, two attractant and two repellent sources at sampled
// positions. scenes/paper-cue-N.json is this scene (a test checks it).
Scene paper_cue_scene(std::uint64_t neurons);

}  // namespace axg::bench
