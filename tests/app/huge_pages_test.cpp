// The command's operator new (app/huge_pages.cpp, compiled into this test as into the
// command): blocks of 32 MB and more are advised onto huge pages and touched in parallel
// as they are allocated. What a caller sees must not change: value-initialised memory
// reads zero, a filled one its value, and a vector that grows past the threshold keeps
// its elements. (The touch's isolation, which keeps a thread waiting for it from running
// another iteration of a loop that allocated, is not shown here: a test that allocates
// inside a parallel loop passed with the isolation removed too, the scheduler never
// having taken an outer iteration.)
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(huge_pages, LargeBlocksReadAsTheirInitialisationSays) {
  std::vector<std::uint8_t> zeros(40 * kMiB);
  for (std::size_t i = 0; i < zeros.size(); i += 4093) ASSERT_EQ(zeros[i], 0) << i;
  ASSERT_EQ(zeros.back(), 0);
  std::vector<std::uint64_t> filled(6 * kMiB, 0x5a5a5a5a5a5a5a5aull);  // 48 MB
  for (std::size_t i = 0; i < filled.size(); i += 511) ASSERT_EQ(filled[i], 0x5a5a5a5a5a5a5a5aull) << i;
}

TEST(huge_pages, AVectorGrowingPastTheThresholdKeepsItsElements) {
  std::vector<std::uint32_t> v;
  for (std::uint32_t i = 0; i < 20 * kMiB; ++i) v.push_back(i * 2654435761u);  // ends at 80 MB, reallocating past 32
  for (std::uint32_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], i * 2654435761u) << i;
}

}  // namespace
