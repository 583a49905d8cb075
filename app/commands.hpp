#pragma once
#include <exception>
// The subcommands of `axonguide` (SPEC §6). Each returns the process exit code.
#include <string>
#include <vector>

namespace axg::app {

struct RunArgs {
  std::string scene_path;  // empty: the built-in default
  std::string out_dir = "out";
  int threads = 0;
  std::string backend = "reference";
  std::string seed;        // with seed_given: overrides the scene's
  bool seed_given = false;
  bool out_given = false;
  bool quiet = false;
  bool vtk = false;
  bool force = false;      // replace the run that --out holds
  std::string resume;      // continue the run in this folder
};

int cmd_verify(const std::string& dir);

int cmd_run(const RunArgs& args);
int cmd_scene_default();
int cmd_scene_check(const std::string& path);

struct BenchArgs {
  std::string what = "all";
  std::string backend = "reference";
  bool json = false;
  bool quick = false;
  int threads = 0;
};
int cmd_bench(const BenchArgs& args);

struct ValidateArgs {
  std::string what = "all";
  std::string report = "validation";
  bool quick = false;
  int threads = 0;
  std::string points;
  double radius = 1.0;
  bool allow_skip = false;  // exit 0, not 3, when a check is skipped (e.g. validate gpu without a GPU)
};
int cmd_validate(const ValidateArgs& args);

struct GoldenArgs {
  std::string action;  // check | bless
  std::string reason;
  std::string dir;     // default: data/golden
  std::string only;
  std::string backend = "reference";
  int threads = 0;
};
int cmd_golden(const GoldenArgs& args);

int cmd_view(const std::string& dir);
int cmd_assay(const std::string& dir);

struct MorphometryArgs {
  std::string dir;               // a run's folder (its morphologies/) or a folder of .swc files
  std::string out;               // empty: dir
  std::string projection = "none";  // none | xy (lengths and Sholl radii in the xy plane)
  double sholl_step = 10.0;      // µm
};
int cmd_morphometry(const MorphometryArgs& args);

// A file of a run's folder, whole; InputError "WHAT: cannot read PATH" when it cannot be
// read (app/study_command.cpp; the assay and network commands read neurons.csv with it).
std::string read_file(const std::filesystem::path& p, const char* what);

struct NetworkArgs {
  std::string dir;   // a run's folder
  std::string out;   // empty: dir
  double bin = 25.0;  // µm: the connection probability's distance bins
};
int cmd_network(const NetworkArgs& args);

struct SweepArgs {
  std::string spec_path;
  std::string out_dir;
  int threads = 0;
  std::string backend = "reference";
  bool quiet = false;
};
int cmd_sweep(const SweepArgs& args);

// Prints the one line a failed command prints (main's, and rank 0's under mpirun, which
// must print before MPI_Finalize lets the other ranks exit) and returns its exit code.
int report_error(std::exception_ptr error);

struct FitArgs {
  std::string data_path, scene_path, out_dir;
  double max_chi2 = 3.0;
  bool scale = false;
  int seeds = 4;
  int max_seeds = 64;
  int polish = 4;
  double target_se = 1.0 / 3.0;
  bool mirror = true;
  bool antithetic = true;
  std::vector<std::string> params, corrections;
  std::string bias_metric;
  double gain_lo = 1, gain_hi = 1000;
  int coarse = 7, refine = 2;
  int threads = 0;
  std::string backend = "reference";
  bool profile = false;  // morphometric fits: profile intervals
};
int cmd_fit(const FitArgs& args);
int cmd_plot(const std::string& dir);

}  // namespace axg::app
