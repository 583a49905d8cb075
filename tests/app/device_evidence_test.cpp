// GPU evidence that cannot pass by accident: a skip is never a pass (reports, `validate
// gpu`, the bundle's run-tests.sh), a failed benchmark run has no figure, no driver gets a
// plain message before any work, and the build says which GPUs it can run.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "axonguide/accel/engines.hpp"
#include "axonguide/validate/report.hpp"
#include "bench.hpp"
#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

using Result = test::ShellResult;

// Runs a shell command line; stdout and stderr captured through files.
Result shell(const std::string& cmd, const test::TempDir& tmp) { return test::shell_capture(cmd, tmp.path()); }
Result axonguide(const std::string& args, const test::TempDir& tmp) { return shell(test::binary() + " " + args, tmp); }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// No NVIDIA driver library on this machine (looked for the way the engine does).
bool no_driver() {
  void* h = ::dlopen("libcuda.so.1", RTLD_LAZY | RTLD_LOCAL);
  if (h) ::dlclose(h);
  return h == nullptr;
}

TEST(report, SkippedIsNotPassedAndExitsThreeUnlessAllowed) {
  test::TempDir tmp;
  {
    validate::Report r(tmp.path() / "pass", "all ran");
    r.check({"ran", true, "1", "1", "0"});
    EXPECT_TRUE(r.passed());
    EXPECT_EQ(r.finish(), 0);
    EXPECT_TRUE(has(test::read_file(tmp.path() / "pass" / "report.md"), "**PASS**"));
  }
  for (bool allow : {false, true}) {
    validate::Report r(tmp.path() / "skip", "one skipped");
    r.check({"ran", true, "1", "1", "0"});
    r.skip("needs a GPU", "no GPU here");
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(r.skipped(), 1u);
    EXPECT_EQ(r.finish(allow), allow ? 0 : 3);
    const std::string md = test::read_file(tmp.path() / "skip" / "report.md");
    EXPECT_TRUE(has(md, "**SKIPPED**")) << md;
    EXPECT_FALSE(has(md, "PASS")) << md;
    EXPECT_EQ(has(md, "allowed by --allow-skip"), allow) << md;
  }
  validate::Report r(tmp.path() / "fail", "skipped and failed");
  r.skip("needs a GPU", "no GPU here");
  r.check({"ran", false, "2", "1", "1 over"});
  EXPECT_EQ(r.finish(true), 1);  // a failure outranks a skip, allowed or not
}

TEST(validate_gpu, SaysSkippedAndExitsThreeWithoutAGpuUnlessAllowed) {
  test::TempDir tmp;
  const std::string why = accel::cuda_unavailable_reason();
  const Result strict = axonguide(fmt::format("validate gpu --report {}/r", tmp.path().string()), tmp);
  if (why.empty()) {
    EXPECT_EQ(strict.code, 0) << strict.out << strict.err;
    EXPECT_TRUE(has(strict.out, "PASS")) << strict.out;
    return;
  }
  EXPECT_EQ(strict.code, 3) << strict.out << strict.err;
  EXPECT_TRUE(has(strict.out, "SKIPPED")) << strict.out;
  EXPECT_FALSE(has(strict.out, "PASS")) << strict.out;
  EXPECT_TRUE(has(strict.err, why)) << strict.err;
  EXPECT_TRUE(has(strict.err, "--allow-skip")) << strict.err;
  EXPECT_TRUE(has(test::read_file(tmp.path() / "r" / "gpu" / "report.md"), "**SKIPPED**"));
  const Result allowed = axonguide(fmt::format("validate gpu --allow-skip --report {}/r", tmp.path().string()), tmp);
  EXPECT_EQ(allowed.code, 0) << allowed.out << allowed.err;
  EXPECT_TRUE(has(allowed.out, "SKIPPED, allowed by --allow-skip")) << allowed.out;
}

// Every command that takes --backend cuda refuses before any work, and before creating
// its output folder: "not built" (exit 2) or, with no driver, "no NVIDIA driver found"
// (exit 3). `bench` prints no figure.
TEST(cuda_backend, NoDriverIsAPlainMessageBeforeAnyWork) {
  if (accel::cuda_built() && !no_driver()) GTEST_SKIP() << "this machine has an NVIDIA driver";
  test::TempDir tmp;
  const std::string t = tmp.path().string(), src = test::source_dir();
  const std::vector<std::pair<std::string, std::string>> commands{
      {"run", fmt::format("run --backend cuda --out {}/run", t)},
      {"bench", "bench growth --quick --backend cuda"},
      {"golden", fmt::format("golden check --backend cuda --dir {}/data/golden", src)},
      {"sweep", fmt::format("sweep {}/scenes/default.sweep.json --backend cuda --out {}/sweep", src, t)},
      {"fit", fmt::format("fit {0}/data/assay/bicknell2018-summary.csv --scene {0}/scenes/assay-explant.json "
                          "--backend cuda --out {1}/fit",
                          src, t)}};
  for (const auto& [name, args] : commands) {
    const Result r = axonguide(args, tmp);
    if (!accel::cuda_built()) {
      EXPECT_EQ(r.code, 2) << name << ": " << r.err;
      EXPECT_TRUE(has(r.err, "not built")) << name << ": " << r.err;
    } else {
      EXPECT_EQ(r.code, 3) << name << ": " << r.err;
      EXPECT_TRUE(has(r.err, "no NVIDIA driver found")) << name << ": " << r.err;
    }
    EXPECT_FALSE(has(r.out, "/s")) << name << " printed a figure: " << r.out;
    EXPECT_FALSE(fs::exists(tmp.path() / name)) << name << " created its output folder";
  }
}

TEST(bench_rows, AFailedRunHasNoFigure) {
  const bench::Row ok{"end-to-end", "paper-direct-5000", "axonguide cuda", 16, 5000, 2.5, 2000, "neurons/s", 114.2,
                      "report Table 4", "exit 0"};
  EXPECT_TRUE(has(bench::format_row(ok), "2.5000 s")) << bench::format_row(ok);
  EXPECT_TRUE(has(bench::format_row(ok), "114.20x")) << bench::format_row(ok);
  const bench::Row bad = bench::failed_row("end-to-end", "paper-direct-5000", "axonguide cuda", 16, 5000, "neurons/s",
                                           "axonguide run exited 3");
  EXPECT_TRUE(bad.failed);
  EXPECT_EQ(bad.seconds, 0);
  EXPECT_EQ(bad.ratio, 0);
  const std::string line = bench::format_row(bad);
  EXPECT_TRUE(has(line, "FAILED: axonguide run exited 3")) << line;
  EXPECT_FALSE(has(line, "neurons/s")) << line;
  EXPECT_FALSE(has(line, " x vs")) << line;
}

// What the engine says about a GPU the build has no code for, and what it runs.
TEST(cuda_arch, RefusesAComputeCapabilityTheBuildCannotRunAndNamesIt) {
  const std::string def = "80-real,90-real,90-virtual";
  for (auto [major, minor] : {std::pair{8, 0}, {8, 6}, {8, 9}, {9, 0}, {10, 0}, {12, 0}})
    EXPECT_EQ(accel::cuda_arch_refusal(major, minor, def), "") << major << "." << minor;
  for (auto [major, minor] : {std::pair{7, 5}, {7, 0}, {6, 1}}) {
    const std::string why = accel::cuda_arch_refusal(major, minor, def);
    EXPECT_TRUE(has(why, fmt::format("compute capability {}.{}", major, minor))) << why;
    EXPECT_TRUE(has(why, "sm_80") && has(why, "sm_90") && has(why, "compute_90")) << why;
    EXPECT_TRUE(has(why, fmt::format("-DCMAKE_CUDA_ARCHITECTURES=\"{}{}-real;80-real;90-real;90-virtual\"", major,
                                     minor)))
        << why;
  }
  EXPECT_NE(accel::cuda_arch_refusal(10, 0, "90-real"), "");  // SASS only: no JIT for newer GPUs
  EXPECT_NE(accel::cuda_arch_refusal(8, 0, "86-real"), "");   // sm_86 code does not run on 8.0
  EXPECT_EQ(accel::cuda_arch_refusal(8, 9, "86-real"), "");
  EXPECT_EQ(accel::cuda_arch_refusal(9, 0, "90a-real"), "");
  EXPECT_NE(accel::cuda_arch_refusal(10, 0, "90a-virtual"), "");  // arch-specific PTX: 9.0 only
  EXPECT_EQ(accel::cuda_arch_refusal(9, 0, "80-virtual"), "");
  EXPECT_EQ(accel::cuda_arch_refusal(12, 0, "90"), "");  // plain 90 is sm_90 and compute_90
  EXPECT_EQ(accel::cuda_arch_refusal(7, 5, "native"), "");  // CMake's to resolve: not judged
  EXPECT_EQ(accel::cuda_arch_refusal(7, 5, "all-major"), "");
}

// The build runs on H100/H200 (9.0) and, through PTX, on newer GPUs (cmake/AxgCuda.cmake).
TEST(cuda_arch, TheBuildCoversSm90AndNewerThroughPtx) {
  if (!accel::cuda_built()) {
    EXPECT_EQ(accel::cuda_architectures(), "");
    GTEST_SKIP() << "the CUDA engine was not built: " << accel::cuda_refusal();
  }
  const std::string archs = accel::cuda_architectures();
  for (auto [major, minor] : {std::pair{9, 0}, {10, 0}, {12, 0}})
    EXPECT_EQ(accel::cuda_arch_refusal(major, minor, archs), "") << archs;
  EXPECT_NE(accel::cuda_arch_refusal(8, 0, archs), "") << archs;  // no sm_80 unless asked for
}

// Fixtures for the bundle test below: real GoogleTest output, one passing and one
// skipping, produced by running this binary on one disabled test.
TEST(bundle_fixture, DISABLED_Passes) { SUCCEED(); }
TEST(bundle_fixture, DISABLED_Skips) { GTEST_SKIP() << "no GPU (fixture)"; }

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

// A fake bundle around scripts/bundle-run-tests.sh: test binaries that pass, skip or fail,
// and an axonguide whose cuda commands cannot run (exit 3) while the reference passes.
struct FakeBundle {
  test::TempDir tmp;
  fs::path dir = tmp.path() / "bundle";

  FakeBundle(bool with_failure) {
    fs::create_directories(dir / "tests");
    fs::create_directories(dir / "bin");
    // The source tree's script, or inside a bundle (AXG_SOURCE_DIR is the bundle) its own.
    const fs::path script = fs::path(test::source_dir()) / "scripts" / "bundle-run-tests.sh";
    fs::copy_file(fs::exists(script) ? script : fs::path(test::source_dir()) / "run-tests.sh", dir / "run-tests.sh");
    write("env.sh", "here=$(cd \"$(dirname \"${BASH_SOURCE[0]}\")\" && pwd)\n");
    const std::string self = self_exe();
    // Each records its arguments, then runs one fixture with real GoogleTest output.
    auto binary = [&](const std::string& name, const std::string& test) {
      write("tests/" + name,
            fmt::format("#!/usr/bin/env bash\necho \"$@\" >> \"$(dirname \"$0\")/../args.txt\"\n"
                        "exec {} --gtest_filter=bundle_fixture.DISABLED_{} --gtest_also_run_disabled_tests\n",
                        self, test));
    };
    binary("a_test", "Passes");
    binary("gpu_test", "Skips");
    if (with_failure) write("tests/broken_test", "#!/usr/bin/env bash\necho '[  FAILED  ] 1 test'\nexit 1\n");
    write("bin/axonguide",
          "#!/usr/bin/env bash\necho \"$@\" >> \"$(dirname \"$0\")/../axonguide-args.txt\"\n"
          "case \"$*\" in *cuda*|*gpu*) echo 'axonguide: cannot run: --backend cuda: no NVIDIA driver found' >&2; "
          "exit 3;; esac\nexit 0\n");
  }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    ::chmod((dir / name).c_str(), 0755);
  }
  Result run(const std::string& args) { return shell(fmt::format("{}/run-tests.sh {}", dir.string(), args), tmp); }
};

TEST(bundle, RunTestsSaysSkippedAndExitsThreeUnlessAllowed) {
  FakeBundle b(false);
  const Result r = b.run("--gtest_color=no");
  EXPECT_EQ(r.code, 3) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "PASS a_test (1 tests)")) << r.out;
  EXPECT_TRUE(has(r.out, "SKIPPED gpu_test (1 of 1 tests skipped")) << r.out;
  EXPECT_TRUE(has(r.out, "PASS golden check --backend reference")) << r.out;
  EXPECT_TRUE(has(r.out, "SKIPPED golden check --backend cuda (axonguide: cannot run: --backend cuda: no NVIDIA"))
      << r.out;
  EXPECT_TRUE(has(r.out, "SKIPPED validate gpu")) << r.out;
  EXPECT_TRUE(has(r.out, "run-tests: 2 passed, 0 failed, 3 skipped")) << r.out;
  EXPECT_FALSE(has(r.out, "PASS gpu_test")) << r.out;
  // The golden check runs on the cuda backend too.
  EXPECT_TRUE(has(test::read_file(b.dir / "axonguide-args.txt"), "golden check --backend cuda"));

  const Result allowed = b.run("--allow-skip --gtest_color=no");
  EXPECT_EQ(allowed.code, 0) << allowed.out << allowed.err;
  EXPECT_TRUE(has(allowed.out, "SKIPPED gpu_test (1 of 1 tests skipped, allowed by --allow-skip")) << allowed.out;
  // --allow-skip is the script's; the other arguments reach the test binaries.
  const std::string args = test::read_file(b.dir / "args.txt");
  EXPECT_FALSE(has(args, "--allow-skip")) << args;
  EXPECT_TRUE(has(args, "--gtest_color=no")) << args;
}

TEST(bundle, RunTestsFailsOnAFailureEvenWithAllowSkip) {
  FakeBundle b(true);
  const Result r = b.run("--allow-skip");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "FAIL broken_test (exit 1")) << r.out;
}

}  // namespace
}  // namespace axg
