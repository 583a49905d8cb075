#include "axonguide/validate/validate.hpp"

#include <chrono>
#include <fstream>
#include <functional>

#include <fmt/format.h>

#include "axonguide/error.hpp"
#include "axonguide/version.hpp"

namespace axg::validate {

namespace fs = std::filesystem;

namespace {

struct Study {
  const char* name;
  const char* title;
  void (*run)(const Options&, Report&);
};

const Study kStudies[] = {
    {"samplers", "Sampler uniformity", validate_samplers},
    {"field", "Cue fields: error against run time", validate_field},
    {"stiff", "Stiff and extreme cases", validate_stiff},
    {"turning", "The SNR turning model", validate_turning},
    {"guidance", "Particle sensing and guidance: flat field, convergence, persistence", validate_guidance},
    {"assay", "The explant assay: control, steepness, peak concentration", validate_assay},
    {"bfs", "BFS and components against Boost.Graph", validate_bfs},
    {"gpu", "Reference against the CUDA accelerator", validate_gpu},
};

int run_one(const Study& s, const fs::path& dir, const Options& o, double* seconds) {
  Report r(dir, s.title);
  const auto t0 = std::chrono::steady_clock::now();
  if (std::string(s.name) == "samplers" && !o.points_file.empty()) validate_points_file(o, r);
  else s.run(o, r);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.text(fmt::format("Run time: {:.1f} s{}.", *seconds, o.quick ? " (--quick)" : ""));
  return r.finish();
}

}  // namespace

int run_validation(const std::string& what, const std::string& dir, const Options& o) {
  if (what != "all") {
    for (const Study& s : kStudies)
      if (what == s.name) {
        double secs;
        return run_one(s, fs::path(dir) / s.name, o, &secs);
      }
    throw InputError("validate: unknown study '" + what + "'");
  }
  std::string index = fmt::format("# axonguide validation\n\naxonguide {} ({}){}.\n\n| study | result | time |\n|---|---|---|\n",
                                  kVersion, kCommit, o.quick ? ", --quick" : "");
  int worst = 0;
  for (const Study& s : kStudies) {
    double secs = 0;
    const int rc = run_one(s, fs::path(dir) / s.name, o, &secs);
    worst = std::max(worst, rc);
    index += fmt::format("| [{}]({}/report.md) | {} | {:.1f} s |\n", s.title, s.name, rc ? "**FAIL**" : "pass", secs);
  }
  fs::create_directories(dir);
  std::ofstream(fs::path(dir) / "report.md") << index;
  std::printf("validation: %s -> %s/report.md\n", worst ? "FAIL" : "PASS", dir.c_str());
  return worst;
}

}  // namespace axg::validate
