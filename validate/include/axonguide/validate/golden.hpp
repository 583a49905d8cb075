#pragma once
// Golden networks (data/golden/NAME/): scene.json, the expected outputs (every file of a
// run except timings.csv and manifest.json) under expected/, and provenance.json (seed,
// canonical scene, version, commit, compiler and flags, date, the reason of the last
// bless, the SHA-256 of each expected file). `golden check` reruns every scene and
// compares the bytes; `golden bless --reason TEXT` regenerates them and appends the
// reason to data/golden/CHANGELOG.md.
#include <filesystem>
#include <string>
#include <vector>

#include "axonguide/engine/run.hpp"

namespace axg::validate {

struct GoldenResult {
  std::string name;
  bool pass = true;
  bool verified = true;  // false: the network's files do not match its provenance (not run)
  std::vector<std::string> differences;  // "neurons.csv line 17: expected ... got ...", or why unverified
};

// data/golden from the working directory, else from the source tree.
std::filesystem::path default_golden_dir();

std::vector<GoldenResult> golden_check(const std::filesystem::path& dir, const EngineFactory& make, int threads);

// Regenerates every golden network (or only `only`); returns the names whose outputs
// changed. Appends to CHANGELOG.md.
std::vector<std::string> golden_bless(const std::filesystem::path& dir, const std::string& reason, int threads,
                                      const std::string& only = "");

}  // namespace axg::validate
