#pragma once
// Helpers shared by the tests: temporary directories, running scenes, hashing outputs.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <rapidcheck.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/threads.hpp"

namespace axg::test {

namespace fs = std::filesystem;

// The source tree (scenes, data, test tables) and the built command; the environment
// variables of the same names override the paths compiled in (for relocated bundles).
inline std::string source_dir() {
  const char* env = std::getenv("AXG_SOURCE_DIR");
  return env && *env ? env : AXG_SOURCE_DIR;
}
inline std::string binary() {
  const char* env = std::getenv("AXG_BINARY");
  return env && *env ? env : AXG_BINARY;
}

// A fresh directory, removed with its content when the object dies.
// scenes/*.sweep.json are sweep files (docs/methods.md §12.2), not scenes.
inline bool is_sweep_file(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.size() > 11 && name.compare(name.size() - 11, 11, ".sweep.json") == 0;
}

class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() / fmt::format("axg-test-{}-{}", ::getpid(), counter++);
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// SHA-256 of every output file, in the folder and its subfolders (morphologies/, vtk/,
// network/), by its path in the folder, except the ones allowed to vary (timings, manifest).
inline std::map<std::string, std::string> output_hashes(const fs::path& dir) {
  std::map<std::string, std::string> h;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string name = fs::relative(e.path(), dir).generic_string();
    if (name == "timings.csv" || name == "manifest.json") continue;
    h[name] = sha256_file(e.path());
  }
  return h;
}

// Runs a scene on `threads` threads with the given engine and returns the output hashes.
inline std::map<std::string, std::string> run_hashes(const Scene& scene, int threads,
                                                     const EngineFactory& make = {}) {
  TempDir dir;
  RunOptions options;
  options.make_engine = make;
  const RunResult r = with_threads(threads, [&] { return run_scene(scene, options); });
  write_outputs(r, dir.path(), "test", threads, {});
  return output_hashes(dir.path());
}

// Small random scenes for properties: every sampler, region, contact rule, overlap mode.
inline rc::Gen<Scene> gen_direct_scene() {
  return rc::gen::exec([] {
    Scene s;
    s.seed = *rc::gen::arbitrary<std::uint64_t>();
    s.steps = *rc::gen::inRange<std::uint32_t>(1, 60);
    s.neurons.count = *rc::gen::inRange<std::uint64_t>(1, 400);
    s.neurons.shape = *rc::gen::element(RegionShape::kBall, RegionShape::kSphere, RegionShape::kBox);
    s.neurons.sampler =
        *rc::gen::element(Sampler::kRejection, Sampler::kNormal, Sampler::kTrig, Sampler::kCoordinate);
    s.neurons.radius = *rc::gen::inRange(20, 80) / 10.0;
    s.neurons.soma_radius = *rc::gen::inRange(5, 40) / 100.0;
    s.neurons.overlap_reject = *rc::gen::arbitrary<bool>();
    s.axons.step_length = *rc::gen::inRange(5, 100) / 100.0;
    s.axons.contact_distance = *rc::gen::inRange(0, 20) / 100.0;
    s.axons.contact = *rc::gen::element(ContactRule::kSwept, ContactRule::kEndpoint);
    if (*rc::gen::arbitrary<bool>()) s.axons.bounds_radius = s.neurons.radius * 1.5;
    s.guidance.model = GuidanceModel::kDirect;
    s.analysis.bfs_sources = {0};
    s.output.paths = *rc::gen::arbitrary<bool>();
    s.output.stats_every = *rc::gen::inRange<std::uint32_t>(1, 5);
    return s;
  });
}

// Placements for properties: every region, three samplers, packing fractions from 0.01
// to 0.45 (past RSA's jamming near 0.38), attempt limits low enough to fail, and two
// populations; up to max_count somas, ids across many placement blocks.
inline rc::Gen<Scene> gen_placement_scene(std::uint64_t max_count) {
  return rc::gen::exec([max_count] {
    Scene s;
    s.seed = *rc::gen::arbitrary<std::uint64_t>();
    s.neurons.count = *rc::gen::inRange<std::uint64_t>(2, max_count);
    s.neurons.shape = *rc::gen::element(RegionShape::kBall, RegionShape::kBox, RegionShape::kSphere);
    s.neurons.sampler = *rc::gen::element(Sampler::kRejection, Sampler::kNormal, Sampler::kTrig);
    s.neurons.radius = 10.0;
    const double phi = *rc::gen::element(0.01, 0.1, 0.3, 0.45);
    const double n = static_cast<double>(s.neurons.count);
    s.neurons.soma_radius = s.neurons.shape == RegionShape::kSphere ? 10.0 * std::sqrt(4.0 * phi / n)
                                                                    : 10.0 * std::cbrt(phi / n);
    s.neurons.max_attempts = *rc::gen::element(1u, 5u, 1000u);
    if (*rc::gen::element(false, true) && s.neurons.shape != RegionShape::kSphere) {
      s.neurons.populations = {Population{s.neurons.count / 2, {-4.0, 0, 0}, 5.0},
                               Population{s.neurons.count - s.neurons.count / 2, {4.0, 0, 0}, 5.0}};
      // The larger population (an odd count's second) sets the packing: at most 0.3, below
      // the up-front refusal of a population past jamming (0.38).
      const double larger = static_cast<double>(s.neurons.count - s.neurons.count / 2);
      s.neurons.soma_radius = 5.0 * std::cbrt(std::min(phi, 0.3) / larger);
    }
    return s;
  });
}

// Count-based sensing: the count noise form (the default; set explicitly so that a test
// does not depend on the default).
inline void use_count_sensing(Scene& s) { s.guidance.noise = core::NoiseForm::kCount; }

// The command (binary()) with these arguments, through the shell: its exit code, and what
// it printed on both streams.
inline std::pair<int, std::string> run_command(const std::string& args) {
  const std::string cmd = fmt::format("{} {} 2>&1", binary(), args);
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  char buf[512];
  while (p && std::fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? ::pclose(p) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, out};
}

inline std::string read_file(const fs::path& p) {
  std::FILE* f = std::fopen(p.c_str(), "rb");
  if (!f) return {};
  std::string s;
  char buf[65536];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  std::fclose(f);
  return s;
}

// n bytes that differ from position to position and with the salt (a linear congruential
// sequence's high bytes): file contents for the output tests.
inline std::string byte_pattern(std::size_t n, std::uint32_t salt) {
  std::string s(n, '\0');
  std::uint32_t x = salt * 2654435761u + 1;
  for (std::size_t i = 0; i < n; ++i) x = x * 1664525u + 1013904223u, s[i] = static_cast<char>(x >> 24);
  return s;
}

// Whether the file system of dir takes an aligned direct write (O_DIRECT).
inline bool direct_io_works(const fs::path& dir) {
  const fs::path probe = dir / ".direct-probe";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_DIRECT, 0644);
  if (fd < 0) return false;
  void* p = nullptr;
  bool ok = ::posix_memalign(&p, 4096, 4096) == 0;
  if (ok) {
    std::memset(p, 0, 4096);
    ok = ::write(fd, p, 4096) == 4096;
  }
  std::free(p);
  ::close(fd);
  std::error_code ec;
  fs::remove(probe, ec);
  return ok;
}

// The file-size limit (RLIMIT_FSIZE) lowered to `bytes` while it lives, with SIGXFSZ
// ignored (as the command ignores it): a write past it fails with EFBIG, on whichever
// thread makes it. std::runtime_error when the limit cannot be set.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    if (::getrlimit(RLIMIT_FSIZE, &before_) != 0) throw std::runtime_error("getrlimit(RLIMIT_FSIZE) failed");
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = before_;
    limit.rlim_cur = bytes;
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) {
      std::signal(SIGXFSZ, old_handler_);
      throw std::runtime_error("setrlimit(RLIMIT_FSIZE) failed");
    }
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &before_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit before_{};
  void (*old_handler_)(int) = SIG_DFL;
};

// A shell command line's exit code (128 + the signal when one ended it), stdout and stderr,
// captured through files in `dir`.
struct ShellResult {
  int code;
  std::string out, err;
};
inline ShellResult shell_capture(const std::string& cmd, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const int status = std::system(fmt::format("{} >{} 2>{}", cmd, out.string(), err.string()).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), read_file(out), read_file(err)};
}

}  // namespace axg::test
