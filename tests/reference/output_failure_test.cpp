// A file that cannot be written while the outputs are (a full disk, a file-size limit) is
// a RunError that names it, with no temporary file left behind, for the writers that do not
// write through AtomicFile::write alone: graph.graphml, which Boost.Graph writes through an
// std::ostream, and SONATA's HDF5 files, which HDF5 writes itself.
#include <gtest/gtest.h>

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
  std::string error;
  {
    test::FileSizeLimit limit(kLimit);
    try {
      write_outputs(r, dir.path(), "test", 1, {});
    } catch (const RunError& e) {
      error = e.what();
    }
  }
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
      test::FileSizeLimit l(static_cast<rlim_t>(limit));
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
