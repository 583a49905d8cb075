#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fstream>
#include <sstream>

#include "axonguide/core/random.hpp"
#include "support.hpp"

namespace axg::core {
namespace {

TEST(random, PhiloxKnownAnswers) {
  std::ifstream in(test::source_dir() + "/tests/data/kat_philox4x32_10.txt");
  ASSERT_TRUE(in) << "missing KAT table";
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string name;
    int rounds;
    std::uint32_t v[10];
    ss >> name >> std::dec >> rounds;
    for (auto& x : v) ss >> std::hex >> x;
    ASSERT_EQ(name, "philox4x32");
    ASSERT_EQ(rounds, 10);
    r123::Philox4x32 rng;
    r123::Philox4x32::ctr_type ctr = {{v[0], v[1], v[2], v[3]}};
    r123::Philox4x32::key_type key = {{v[4], v[5]}};
    auto out = rng(ctr, key);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(out.v[k], v[6 + k]) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

TEST(random, CounterLayout) {
  // counter = { tag | (id >> 32) << 8, id & 0xffffffff, step, block }
  const Counter c = make_counter(Stream::kParticleMotion, 0x0012345689abcdefull, 77);
  EXPECT_EQ(c.tag_id_hi, 5u | (0x00123456u << 8));
  EXPECT_EQ(c.id_lo, 0x89abcdefu);
  EXPECT_EQ(c.step, 77u);
  // key = { seed lo, seed hi }
  r123::Philox4x32 rng;
  auto direct = rng({{c.tag_id_hi, c.id_lo, 77, 3}}, {{0x9abcdef0u, 0x12345678u}});
  auto ours = philox_block(0x123456789abcdef0ull, c, 3);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(direct.v[k], ours.v[k]);
}

TEST(random, UniformConversionsAreExactAndInRange) {
  EXPECT_EQ(u01_open(0), 0x1p-53);
  EXPECT_EQ(u01_open(~0ull), 1.0 - 0x1p-53);
  EXPECT_EQ(u01_closed_open(0), 0.0);
  EXPECT_EQ(u01_closed_open(~0ull), 1.0 - 0x1p-53);
  // Symmetry of the open grid: u(w) + u(~w) == 1 exactly.
  for (std::uint64_t w : {0ull, 1ull, 12345678901234567ull, ~0ull >> 1, ~0ull})
    EXPECT_EQ(u01_open(w) + u01_open(~w), 1.0);
}

RC_GTEST_PROP(random, OpenUniformIsExactOddMultiple, (std::uint64_t w)) {
  const double u = u01_open(w);
  RC_ASSERT(u > 0.0);
  RC_ASSERT(u < 1.0);
  // u * 2^53 is the odd integer 2k+1 exactly.
  const double scaled = u * 0x1p53;
  RC_ASSERT(scaled == static_cast<double>(((w >> 12) << 1) | 1u));
  const double sym = 2.0 * u - 1.0;
  RC_ASSERT(sym > -1.0 && sym < 1.0);
}

RC_GTEST_PROP(random, RngIsAPureFunctionOfItsCoordinates,
              (std::uint64_t seed, std::uint64_t id, std::uint32_t step)) {
  const std::uint64_t id56 = id & ((1ull << 56) - 1);
  Rng a(seed, Stream::kPlacement, id56, step), b(seed, Stream::kPlacement, id56, step);
  for (int k = 0; k < 9; ++k) RC_ASSERT(a.uniform() == b.uniform());
  // The n-th double is built from words 2(n mod 2), 2(n mod 2)+1 of block n/2.
  Rng c(seed, Stream::kPlacement, id56, step);
  for (std::uint32_t n = 0; n < 6; ++n) {
    const auto blk = philox_block(seed, make_counter(Stream::kPlacement, id56, step), n / 2);
    const int w = static_cast<int>(2 * (n % 2));
    RC_ASSERT(c.uniform() == u01_open(join64(blk.v[w], blk.v[w + 1])));
  }
  // Streams with different tags differ.
  Rng d(seed, Stream::kAxonDirection, id56, step);
  Rng e(seed, Stream::kPlacement, id56, step);
  RC_ASSERT(d.uniform() != e.uniform());
}

}  // namespace
}  // namespace axg::core
