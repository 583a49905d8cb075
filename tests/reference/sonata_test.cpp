// SONATA output (docs/guide.md §1.2): the five files under network/, byte for byte the
// same for 1 and 2 threads, for a second run in the same process and a second write a
// second later (no HDF5 timestamps), and listed in a manifest that verifies. What the
// files say is checked by tests/python/test_sonata.py with h5py and PyNN.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "axonguide/io/sonata.hpp"
#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

Scene small_scene() {
  Scene s;
  s.seed = 3;
  s.steps = 60;
  s.neurons.count = 400;
  s.neurons.radius = 3.0;
  s.guidance.model = GuidanceModel::kDirect;
  s.output.sonata = true;
  return s;
}

std::map<std::string, std::string> sonata_bytes(const RunResult& r, const fs::path& dir) {
  OutputInfo info;
  write_sonata(r, dir, info);
  std::map<std::string, std::string> bytes;
  EXPECT_EQ(info.files.size(), std::size(kSonataFiles));
  for (std::size_t k = 0; k < info.files.size() && k < std::size(kSonataFiles); ++k) {
    const auto& [name, hash] = info.files[k];
    EXPECT_EQ(name, kSonataFiles[k]);
    EXPECT_EQ(hash, sha256_file(dir / name)) << name;
    bytes[name] = test::read_file(dir / name);
  }
  for (const auto& e : fs::directory_iterator(dir / "network"))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  return bytes;
}

RunResult run_on(int threads, const Scene& s) {
  return with_threads(threads, [&] { return run_scene(s, RunOptions{}); });
}

TEST(sonata, BytesEqualForOneAndTwoThreadsAndAgain) {
  const Scene s = small_scene();
  test::TempDir a, b, c, d;
  const RunResult r1 = run_on(1, s);
  ASSERT_GT(r1.stats.back().connected, 10u) << "the scene should connect some axons";
  const auto one = sonata_bytes(r1, a.path());
  const RunResult r2 = run_on(2, s);
  const auto two = with_threads(2, [&] { return sonata_bytes(r2, b.path()); });
  // A second run in the same process: HDF5's free lists now hold blocks of the first.
  const auto again = sonata_bytes(run_on(2, s), c.path());
  // HDF5 would stamp objects with the time (1 s resolution): write again a second later.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  const auto later = sonata_bytes(r1, d.path());
  ASSERT_EQ(one.size(), 5u);
  for (const auto& [name, bytes] : one) {
    EXPECT_GT(bytes.size(), 0u) << name;
    EXPECT_TRUE(bytes == two.at(name)) << name << ": 1 and 2 threads differ";
    EXPECT_TRUE(bytes == again.at(name)) << name << ": a second run differs";
    EXPECT_TRUE(bytes == later.at(name)) << name << ": a write one second later differs";
  }
  // Root attributes as SONATA requires them, visible in the bytes: the HDF5 signature.
  EXPECT_EQ(one.at("network/nodes.h5").substr(0, 8), std::string("\x89HDF\r\n\x1a\n", 8));
  const auto config = nlohmann::json::parse(one.at("network/circuit_config.json"));
  EXPECT_EQ(config["target_simulator"], "PyNN");
  EXPECT_EQ(config["manifest"]["$BASE_DIR"], ".");
  EXPECT_EQ(config["networks"]["nodes"][0]["nodes_file"], "$BASE_DIR/nodes.h5");
}

// No axon connects: the edge population is empty, and the files are still written.
TEST(sonata, NoConnectionsWritesEmptyEdgePopulation) {
  Scene s = small_scene();
  s.steps = 1;
  s.neurons.count = 20;
  s.neurons.radius = 20.0;
  const RunResult r = run_on(1, s);
  ASSERT_EQ(r.stats.back().connected, 0u);
  test::TempDir a, b;
  const auto x = sonata_bytes(r, a.path()), y = sonata_bytes(r, b.path());
  EXPECT_TRUE(x == y);
}

// The command: `run` with output.sonata lists the files in its manifest, and the folder
// verifies.
TEST(sonata, CommandListsTheFilesAndTheFolderVerifies) {
  test::TempDir tmp;
  const fs::path scene = tmp.path() / "scene.json";
  std::ofstream(scene) << scene_to_json(small_scene()).dump();
  const fs::path out = tmp.path() / "out";
  const std::string run = fmt::format("{} run {} -q --threads 2 --out {} >/dev/null 2>{}", test::binary(),
                                      scene.string(), out.string(), (tmp.path() / "err.txt").string());
  const int status = std::system(run.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::read_file(tmp.path() / "err.txt");
  const auto m = nlohmann::json::parse(test::read_file(out / "manifest.json"));
  for (const char* name : kSonataFiles) {
    ASSERT_TRUE(m["files"].contains(name)) << name << " is not in the manifest";
    EXPECT_EQ(m["files"][name]["sha256"].get<std::string>(), sha256_file(out / name)) << name;
  }
  const int verify = std::system(fmt::format("{} verify {} >/dev/null 2>&1", test::binary(), out.string()).c_str());
  EXPECT_TRUE(WIFEXITED(verify) && WEXITSTATUS(verify) == 0);
  // The same scene through write_outputs in this process gives the command's bytes.
  test::TempDir again;
  const RunResult r = run_on(1, small_scene());
  write_outputs(r, again.path(), "test", 1, {});
  for (const char* name : kSonataFiles)
    EXPECT_EQ(sha256_file(again.path() / name), sha256_file(out / name)) << name;
}

// output.csv = false leaves the network to SONATA: no neurons.csv or connections.csv, the
// same SONATA bytes as beside the CSV, a folder that verifies; without SONATA it is refused
// (exit 2, the key named), since no file would hold the network.
TEST(sonata, WithoutTheCsvTheNetworkIsSonataAlone) {
  test::TempDir tmp;
  Scene s = small_scene();
  s.output.csv = false;
  const fs::path scene = tmp.path() / "scene.json";
  std::ofstream(scene) << scene_to_json(s).dump();
  const fs::path out = tmp.path() / "out";
  const std::string run = fmt::format("{} run {} -q --threads 2 --out {} >/dev/null 2>{}", test::binary(),
                                      scene.string(), out.string(), (tmp.path() / "err.txt").string());
  const int status = std::system(run.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::read_file(tmp.path() / "err.txt");
  EXPECT_FALSE(fs::exists(out / "neurons.csv"));
  EXPECT_FALSE(fs::exists(out / "connections.csv"));
  EXPECT_TRUE(fs::exists(out / "stats.csv"));
  const auto m = nlohmann::json::parse(test::read_file(out / "manifest.json"));
  EXPECT_FALSE(m["files"].contains("neurons.csv"));
  EXPECT_EQ(m["scene"]["output"]["csv"], false);
  const int verify = std::system(fmt::format("{} verify {} >/dev/null 2>&1", test::binary(), out.string()).c_str());
  EXPECT_TRUE(WIFEXITED(verify) && WEXITSTATUS(verify) == 0);
  test::TempDir with_csv;
  write_outputs(run_on(1, small_scene()), with_csv.path(), "test", 1, {});
  for (const char* name : kSonataFiles)
    EXPECT_EQ(sha256_file(with_csv.path() / name), sha256_file(out / name)) << name;
  s.output.sonata = false;
  std::ofstream(scene) << scene_to_json(s).dump();
  const int refused = std::system(fmt::format("{} run {} -q --out {} >/dev/null 2>{}", test::binary(), scene.string(),
                                              (tmp.path() / "refused").string(), (tmp.path() / "err.txt").string())
                                      .c_str());
  EXPECT_TRUE(WIFEXITED(refused) && WEXITSTATUS(refused) == 2);
  EXPECT_NE(test::read_file(tmp.path() / "err.txt").find("output.csv = false"), std::string::npos);
  EXPECT_FALSE(fs::exists(tmp.path() / "refused"));
}

}  // namespace
}  // namespace axg
