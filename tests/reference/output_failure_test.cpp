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

}  // namespace
}  // namespace axg
