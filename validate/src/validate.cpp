#include "axonguide/validate/validate.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
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
    {"continuum", "Guidance with a continuum limit: every numerical parameter refined", validate_continuum},
    {"assay", "The explant assay: control, steepness, peak concentration", validate_assay},
    {"calibration", "Calibration: the signalling model's fits to the explant outgrowth, every χ² regenerated",
     validate_calibration},
    {"branching", "Branching: the BESTL rule against van Pelt's recursion, Yule and the elongation model",
     validate_branching},
    {"synapses", "Synapses: contacts against Steiner's formula, appositions against the crossing term, the hash against "
                 "brute force", validate_synapses},
    {"bfs", "BFS and components against Boost.Graph", validate_bfs},
    {"gpu", "Reference against the CUDA accelerator", validate_gpu},
};

struct Outcome {
  int code;             // Report::finish's
  std::size_t skipped;  // checks that could not run
  double seconds;
};

Outcome run_one(const Study& s, const fs::path& dir, const Options& o) {
  Report r(dir, s.title);
  const auto t0 = std::chrono::steady_clock::now();
  if (std::string(s.name) == "samplers" && !o.points_file.empty()) validate_points_file(o, r);
  else s.run(o, r);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.text(fmt::format("Run time: {:.1f} s{}.", seconds, o.quick ? " (--quick)" : ""));
  const int code = r.finish(o.allow_skip);
  return {code, r.skipped(), seconds};
}

void say_skipped(std::size_t skipped) {
  std::fprintf(stderr,
               "axonguide: validate: SKIPPED: %zu check(s) could not run here, so they prove nothing; exit 3 (pass "
               "--allow-skip to accept skips)\n",
               skipped);
}

}  // namespace

int run_validation(const std::string& what, const std::string& dir, const Options& o) {
  if (what != "all") {
    for (const Study& s : kStudies)
      if (what == s.name) {
        const Outcome out = run_one(s, fs::path(dir) / s.name, o);
        if (out.code == kExitCannotRun) say_skipped(out.skipped);
        return out.code;
      }
    throw InputError("validate: unknown study '" + what + "'");
  }
  std::string index = fmt::format("# axonguide validation\n\naxonguide {} ({}){}.\n\n| study | result | time |\n|---|---|---|\n",
                                  kVersion, kCommit, o.quick ? ", --quick" : "");
  bool failed = false;
  std::size_t skipped = 0;
  for (const Study& s : kStudies) {
    const Outcome out = run_one(s, fs::path(dir) / s.name, o);
    failed = failed || out.code == kExitCheckFailed;
    skipped += out.skipped;
    index += fmt::format("| [{}]({}/report.md) | {} | {:.1f} s |\n", s.title, s.name,
                         out.code == kExitCheckFailed ? "**FAIL**"
                         : out.skipped                ? fmt::format("SKIPPED ({} checks)", out.skipped)
                                                      : "pass",
                         out.seconds);
  }
  fs::create_directories(dir);
  write_file_atomically(dir, "report.md", index);
  std::printf("validation: %s%s -> %s/report.md\n", failed ? "FAIL" : skipped ? "SKIPPED" : "PASS",
              !failed && skipped && o.allow_skip ? ", allowed by --allow-skip" : "", dir.c_str());
  if (failed) return kExitCheckFailed;
  if (skipped && !o.allow_skip) {
    say_skipped(skipped);
    return kExitCannotRun;
  }
  return kExitOk;
}

}  // namespace axg::validate
