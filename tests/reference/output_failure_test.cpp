// A file that cannot be written while the outputs are (a full disk, a file-size limit) is
// a RunError that names it, with no temporary file left behind, for every kind of writer:
// here graph.graphml, which Boost.Graph writes through an std::ostream. An ostream keeps its
// streambuf's exceptions to itself (a badbit) unless told otherwise; before that was
// handled, the stream's buffer flushed again in its destructor and the second failure,
// thrown there, ended the process.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <csignal>
#include <string>

#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

TEST(OutputFailure, AGraphmlThatCannotBeWrittenIsARunErrorAndLeavesNoTemporaryFile) {
  Scene s = Scene::builtin_default();
  s.neurons.count = 25000;  // graph.graphml about 390 B a neuron: two blocks and more
  s.steps = 1;
  s.output.graphml = true;
  const RunResult r = run_scene(s, {});
  test::TempDir dir;
  // The limit lies between the CSV files' sizes and graph.graphml's.
  constexpr rlim_t kLimit = AtomicFile::kDirectBlock + AtomicFile::kDirectBlock / 2;
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = before;
  limit.rlim_cur = kLimit;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string error;
  try {
    write_outputs(r, dir.path(), "test", 1, {});
  } catch (const RunError& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(error.find("cannot write"), std::string::npos) << "no RunError: '" << error << "'";
  EXPECT_NE(error.find("graph.graphml"), std::string::npos) << error;
  // The files before it are whole, below the limit, and nothing is half-written.
  EXPECT_TRUE(fs::exists(dir.path() / "neurons.csv"));
  EXPECT_FALSE(fs::exists(dir.path() / "graph.graphml"));
  for (const auto& e : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path() << " was left behind";
    EXPECT_LT(fs::file_size(e.path()), kLimit) << e.path();
  }
}

// The file-size limit lowered to `bytes` while it lives (SIGXFSZ ignored, as the command
// does): a write past it fails with EFBIG.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    EXPECT_EQ(::getrlimit(RLIMIT_FSIZE, &before_), 0);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = before_;
    limit.rlim_cur = bytes;
    EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &before_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit before_{};
  void (*old_handler_)(int) = SIG_DFL;
};

// SONATA's HDF5 files, failing at their very last byte: HDF5 writes its metadata when the file
// is flushed and closed, after the rows. That failure too is a RunError naming the file, and
// no file is left under its name or a temporary one (the file was once closed only after its
// rename, with the close's errors dropped: a truncated file, hashed and named complete).
TEST(OutputFailure, ASonataFileThatCannotBeFinishedIsARunErrorAndLeavesNothing) {
  Scene s = Scene::builtin_default();
  s.neurons.count = 5000;
  s.steps = 1;
  s.output.sonata = true;
  s.output.csv = false;
  s.output.graphml = false;
  const RunResult r = run_scene(s, {});
  test::TempDir whole;
  write_outputs(r, whole.path(), "test", 1, {});
  std::uintmax_t largest = 0;
  std::string name;
  for (const char* f : {"nodes.h5", "edges.h5"}) {
    const std::uintmax_t size = fs::file_size(whole.path() / "network" / f);
    if (size > largest) {
      largest = size;
      name = f;
    }
  }
  for (const auto& e : fs::recursive_directory_iterator(whole.path())) {
    if (e.is_regular_file() && e.path().filename() != name) {
      ASSERT_LT(fs::file_size(e.path()), largest) << e.path() << ": the limit would stop it too";
    }
  }
  for (const std::uintmax_t limit : {largest - 1, largest / 2}) {
    test::TempDir dir;
    std::string error;
    {
      FileSizeLimit l(static_cast<rlim_t>(limit));
      try {
        write_outputs(r, dir.path(), "test", 1, {});
      } catch (const RunError& e) {
        error = e.what();
      }
    }
    EXPECT_NE(error.find("cannot write"), std::string::npos) << limit << " bytes: no RunError: '" << error << "'";
    EXPECT_NE(error.find(name), std::string::npos) << error;
    EXPECT_FALSE(fs::exists(dir.path() / "network" / name)) << limit << " bytes";
    for (const auto& e : fs::recursive_directory_iterator(dir.path()))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path() << " was left behind";
  }
}

}  // namespace
}  // namespace axg
