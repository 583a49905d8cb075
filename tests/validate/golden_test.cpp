// The golden-network machinery itself: a changed byte is caught and located, bless
// records its reason, and bless without a reason is refused.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/validate/golden.hpp"
#include "support.hpp"

namespace axg {
namespace {

// A private copy of one golden network.
std::filesystem::path copy_one(const test::TempDir& tmp, const std::string& name) {
  const auto src = std::filesystem::path(test::source_dir()) / "data" / "golden" / name;
  const auto dst = tmp.path() / "golden" / name;
  std::filesystem::create_directories(dst.parent_path());
  std::filesystem::copy(src, dst, std::filesystem::copy_options::recursive);
  return dst.parent_path();
}

TEST(golden, ADifferentByteIsCaughtAndLocated) {
  test::TempDir tmp;
  const auto dir = copy_one(tmp, "direct-rejection-ball-swept");
  auto results = validate::golden_check(dir, {}, 2);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_TRUE(results[0].pass);
  // Change one digit on line 3 of neurons.csv.
  const auto f = dir / "direct-rejection-ball-swept" / "expected" / "neurons.csv";
  std::string text = test::read_file(f);
  std::size_t line3 = text.find('\n', text.find('\n') + 1) + 1;
  std::size_t digit = text.find_first_of("0123456789", text.find(',', line3) + 1);
  text[digit] = text[digit] == '1' ? '2' : '1';
  std::ofstream(f, std::ios::binary) << text;
  // As edited, the network no longer verifies against its provenance: refused, unrun.
  results = validate::golden_check(dir, {}, 2);
  EXPECT_FALSE(results[0].pass);
  EXPECT_FALSE(results[0].verified);
  ASSERT_EQ(results[0].differences.size(), 1u);
  EXPECT_NE(results[0].differences[0].find("expected/neurons.csv: SHA-256 differs"), std::string::npos);
  // Blessed that way (provenance re-hashed), it runs, and the run's byte is located.
  const auto prov_path = dir / "direct-rejection-ball-swept" / "provenance.json";
  auto prov = nlohmann::json::parse(test::read_file(prov_path));
  prov["files"]["neurons.csv"] = sha256_file(f);
  std::ofstream(prov_path) << prov.dump(2);
  results = validate::golden_check(dir, {}, 2);
  EXPECT_FALSE(results[0].pass);
  EXPECT_TRUE(results[0].verified);
  ASSERT_EQ(results[0].differences.size(), 1u);
  EXPECT_NE(results[0].differences[0].find("neurons.csv: line 3"), std::string::npos) << results[0].differences[0];
}

// A network folder that lost or changed its scene.json, or gained a file, fails: it is
// never skipped and never run against another scene.
TEST(golden, ANetworkThatDoesNotVerifyFails) {
  test::TempDir tmp;
  const auto dir = copy_one(tmp, "analytic-snr");
  const auto g = dir / "analytic-snr";
  const std::string scene = test::read_file(g / "scene.json");
  std::filesystem::remove(g / "scene.json");
  auto results = validate::golden_check(dir, {}, 1);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].pass);
  EXPECT_EQ(results[0].differences, std::vector<std::string>{"scene.json missing"});
  EXPECT_THROW(validate::golden_bless(dir, "restore", 1), InputError);
  auto j = nlohmann::json::parse(scene);
  j["seed"] = 12345;
  std::ofstream(g / "scene.json") << j.dump();
  results = validate::golden_check(dir, {}, 1);
  EXPECT_FALSE(results[0].pass);
  EXPECT_NE(results[0].differences[0].find("not the scene provenance.json was blessed with"), std::string::npos);
  std::ofstream(g / "scene.json") << scene;
  std::ofstream(g / "expected" / "extra.csv") << "x\n";
  results = validate::golden_check(dir, {}, 1);
  EXPECT_FALSE(results[0].pass);
  EXPECT_NE(results[0].differences[0].find("expected/extra.csv: not listed"), std::string::npos);
  std::filesystem::remove(g / "expected" / "extra.csv");
  EXPECT_TRUE(validate::golden_check(dir, {}, 1)[0].pass);
  // A folder with no network in it at all.
  std::filesystem::create_directories(dir / "stray");
  results = validate::golden_check(dir, {}, 1);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_FALSE(results[1].pass);
  EXPECT_NE(results[1].differences[0].find("provenance.json missing"), std::string::npos);
}

// Bless changes nothing unless it can change everything it was asked to: a file in
// expected/ that provenance.json does not list (someone's notes), or another network without
// its scene, is refused before any network is rendered; and its files are written whole.
TEST(golden, BlessRefusesBeforeItChangesAnything) {
  test::TempDir tmp;
  const auto dir = copy_one(tmp, "analytic-snr");
  const auto g = dir / "analytic-snr";
  auto files = [&] {
    std::map<std::string, std::string> h;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
      if (e.is_regular_file()) h[std::filesystem::relative(e.path(), dir).string()] = test::read_file(e.path());
    return h;
  };
  std::ofstream(g / "expected" / "MY_NOTES.txt") << "mine\n";
  auto before = files();
  try {
    validate::golden_bless(dir, "test", 1);
    ADD_FAILURE() << "blessed over a file provenance.json does not list";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("MY_NOTES.txt: not listed in provenance.json"), std::string::npos) << e.what();
  }
  EXPECT_EQ(files(), before);
  std::filesystem::remove(g / "expected" / "MY_NOTES.txt");
  std::filesystem::create_directories(dir / "zz-notes");
  std::ofstream(dir / "zz-notes" / "todo.txt") << "x\n";
  before = files();
  EXPECT_THROW(validate::golden_bless(dir, "test", 1), InputError);
  EXPECT_EQ(files(), before) << "the first network was blessed before the second was refused";
  EXPECT_THROW(validate::golden_bless(dir, "two\nlines", 1, "analytic-snr"), InputError);
  EXPECT_EQ(validate::golden_bless(dir, "only the one", 1, "analytic-snr"), std::vector<std::string>{});
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(g)) entries += e.path().filename().string()[0] == '.';
  EXPECT_EQ(entries, 0u) << "no scratch folder left beside expected/";
}

TEST(golden, BlessRestoresAndRecordsTheReason) {
  test::TempDir tmp;
  const auto dir = copy_one(tmp, "analytic-snr");
  std::filesystem::remove(dir / "analytic-snr" / "expected" / "stats.csv");
  EXPECT_FALSE(validate::golden_check(dir, {}, 1)[0].pass);
  EXPECT_THROW(validate::golden_bless(dir, "", 1), InputError);
  const auto changed = validate::golden_bless(dir, "unit test: restore stats.csv", 1);
  EXPECT_EQ(changed, std::vector<std::string>{"analytic-snr"});
  EXPECT_TRUE(validate::golden_check(dir, {}, 1)[0].pass);
  EXPECT_NE(test::read_file(dir / "CHANGELOG.md").find("unit test: restore stats.csv"), std::string::npos);
  // The regenerated file equals the committed one: the run is deterministic.
  EXPECT_EQ(test::read_file(dir / "analytic-snr" / "expected" / "stats.csv"),
            test::read_file(std::filesystem::path(test::source_dir()) / "data/golden/analytic-snr/expected/stats.csv"));
}

}  // namespace
}  // namespace axg
