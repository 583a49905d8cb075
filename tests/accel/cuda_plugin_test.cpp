// The CUDA engine is a plugin (accel/src/cuda_plugin.hpp). Without one, with one from another
// build, or with a file that is none, every GPU command exits 2 before any work, saying
// what it found and how to build the right one; never a silent mismatch.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "axonguide/accel/engines.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/version.hpp"
#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

using Result = test::ShellResult;

// `axonguide ARGS` with $AXG_CUDA_ENGINE set to ENGINE (the only place then looked at).
Result with_engine(const std::string& engine, const std::string& args, const test::TempDir& tmp) {
  return test::shell_capture(fmt::format("AXG_CUDA_ENGINE='{}' {} {}", engine, test::binary(), args), tmp.path());
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Each GPU command, refused before it creates its output folder.
std::vector<std::pair<std::string, std::string>> gpu_commands(const test::TempDir& tmp) {
  const std::string t = tmp.path().string(), src = test::source_dir();
  return {{"run", fmt::format("run --backend cuda --out {}/run", t)},
          {"bench", "bench growth --quick --backend cuda"},
          {"golden", fmt::format("golden check --backend cuda --dir {}/data/golden", src)},
          {"sweep", fmt::format("sweep {}/scenes/default.sweep.json --backend cuda --out {}/sweep", src, t)}};
}

TEST(cuda_plugin, MissingIsExitTwoSayingHowToBuildIt) {
  test::TempDir tmp;
  const std::string missing = (tmp.path() / "no" / "libaxg_cuda.so").string();
  for (const auto& [name, args] : gpu_commands(tmp)) {
    const Result r = with_engine(missing, args, tmp);
    EXPECT_EQ(r.code, 2) << name << ": " << r.err;
    EXPECT_TRUE(has(r.err, "not built")) << name << ": " << r.err;
    EXPECT_TRUE(has(r.err, missing)) << name << ": " << r.err;
    EXPECT_TRUE(has(r.err, accel::cuda_configured() ? "cmake --build build --target axg_cuda" : "without nvcc"))
        << name << ": " << r.err;
    EXPECT_FALSE(has(r.out, "/s")) << name << " printed a figure: " << r.out;
    EXPECT_FALSE(fs::exists(tmp.path() / name)) << name << " created its output folder";
  }
}

TEST(cuda_plugin, OneFromAnotherCommitIsExitTwoNamingBothBuilds) {
  test::TempDir tmp;
  const Result r = with_engine(AXG_FOREIGN_COMMIT_PLUGIN, fmt::format("run --backend cuda --out {}/run", tmp.path().string()), tmp);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "commit 0123456789abcdef0123456789abcdef01234567")) << r.err;  // the plugin's
  EXPECT_TRUE(has(r.err, fmt::format("commit {}", kCommit))) << r.err;                  // the command's
  EXPECT_TRUE(has(r.err, "must be one build")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.path() / "run"));
}

TEST(cuda_plugin, AnotherInterfaceIsExitTwo) {
  test::TempDir tmp;
  const Result r = with_engine(AXG_FOREIGN_ABI_PLUGIN, "bench growth --quick --backend cuda", tmp);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "plugin interface")) << r.err;
  EXPECT_TRUE(has(r.err, "rebuild it")) << r.err;
}

TEST(cuda_plugin, AFileThatIsNoPluginIsExitTwo) {
  test::TempDir tmp;
  const fs::path junk = tmp.path() / "libaxg_cuda.so";
  std::ofstream(junk) << "not a shared object\n";
  const Result r = with_engine(junk.string(), fmt::format("run --backend cuda --out {}/run", tmp.path().string()), tmp);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "cannot be loaded")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.path() / "run"));
}

// In process: the reason is the same text the command prints, and the emulated backend
// (which needs no plugin) still runs.
TEST(cuda_plugin, TheReasonIsReportedInProcess) {
  if (accel::cuda_built()) {
    EXPECT_EQ(accel::cuda_refusal(), "");
    EXPECT_FALSE(accel::cuda_architectures().empty());
  } else {
    EXPECT_TRUE(has(accel::cuda_refusal(), "--backend cuda:")) << accel::cuda_refusal();
    EXPECT_TRUE(has(accel::cuda_unavailable_reason(), accel::cuda_refusal()));
    EXPECT_THROW(accel::require_cuda_built(), InputError);
  }
}

}  // namespace
}  // namespace axg
