// The stable radix sort (reference/src/support/radix_sort.cpp) around and above its chunk
// size (kRadixSortChunk = 65,536 keys), where it counts and scatters several chunks in
// parallel: the same bytes as the single-chunk path and as std::stable_sort by key, on 1
// and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "axonguide/core/random.hpp"
#include "axonguide/support/radix_sort.hpp"
#include "axonguide/support/threads.hpp"

namespace axg {
namespace {

struct Keys {
  const char* name;
  std::uint32_t max_key;
};

// max_key sets the passes (11-bit digits): 1 (many ties), 2, and 3 (full 32-bit keys).
constexpr Keys kKinds[] = {{"all equal", 0}, {"16 values", 15}, {"3000 values", 2999}, {"full 32-bit", 0xffffffffu}};

std::vector<std::uint32_t> draw_keys(std::size_t n, std::uint32_t max_key, std::uint64_t seed) {
  std::vector<std::uint32_t> k(n);
  for (std::size_t i = 0; i < n; ++i) {
    core::Rng rng(seed, core::Stream::kValidation, i, 0);
    const std::uint32_t w = rng.word32();
    k[i] = max_key == 0xffffffffu ? w : w % (max_key + 1);
  }
  return k;
}

bool same_bytes(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(std::uint32_t)) == 0;
}

TEST(radix_sort, MultiChunkEqualsSingleChunkAndStdStableSort) {
  const std::size_t sizes[] = {kRadixSortChunk - 1, kRadixSortChunk, kRadixSortChunk + 1, 2 * kRadixSortChunk,
                               2 * kRadixSortChunk + 7, 300001, 1000003};
  for (const std::size_t n : sizes)
    for (const Keys& kind : kKinds) {
      const std::string what = std::to_string(n) + " keys, " + kind.name;
      const std::vector<std::uint32_t> keys = draw_keys(n, kind.max_key, n);
      // Values: a permutation of the ids, so that stability shows in them.
      std::vector<std::uint32_t> values(n);
      std::iota(values.begin(), values.end(), 0u);
      std::reverse(values.begin(), values.end());

      std::vector<std::uint32_t> order(n);
      std::iota(order.begin(), order.end(), 0u);
      std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
      std::vector<std::uint32_t> want_keys(n), want_values(n);
      for (std::size_t i = 0; i < n; ++i) want_keys[i] = keys[order[i]], want_values[i] = values[order[i]];

      std::vector<std::uint32_t> single_keys = keys, single_values = values;
      SortScratch single;
      single.chunk = n;  // one chunk, whatever n
      stable_sort_by_key(single_keys, single_values, kind.max_key, single);
      ASSERT_EQ(single.chunks_used, 1u) << what;
      EXPECT_TRUE(same_bytes(single_keys, want_keys)) << what;
      EXPECT_TRUE(same_bytes(single_values, want_values)) << what;

      for (const int threads : {1, 2}) {
        std::vector<std::uint32_t> k = keys, v = values;
        SortScratch scratch;
        with_threads(threads, [&] { stable_sort_by_key(k, v, kind.max_key, scratch); });
        EXPECT_EQ(scratch.chunks_used, (n + kRadixSortChunk - 1) / kRadixSortChunk) << what;
        if (n > kRadixSortChunk) EXPECT_GT(scratch.chunks_used, 1u) << what << ": the multi-chunk path was not taken";
        EXPECT_TRUE(same_bytes(k, want_keys)) << what << ", " << threads << " threads";
        EXPECT_TRUE(same_bytes(v, want_values)) << what << ", " << threads << " threads";
      }
    }
}

TEST(radix_sort, ReusedScratchAndSmallInputs) {
  SortScratch scratch;
  for (const std::size_t n : {std::size_t{200000}, std::size_t{3}, std::size_t{1}, std::size_t{0}, std::size_t{70000}}) {
    std::vector<std::uint32_t> k = draw_keys(n, 1000, 7), v(n);
    std::iota(v.begin(), v.end(), 0u);
    std::vector<std::uint32_t> want = k;
    std::stable_sort(want.begin(), want.end());
    stable_sort_by_key(k, v, 1000, scratch);
    EXPECT_EQ(k, want) << n;
    for (std::size_t i = 1; i < n; ++i)
      if (k[i] == k[i - 1]) ASSERT_LT(v[i - 1], v[i]) << n << ": not stable at " << i;
    EXPECT_EQ(scratch.chunks_used, n < 2 ? 0u : (n + kRadixSortChunk - 1) / kRadixSortChunk) << n;
  }
}

}  // namespace
}  // namespace axg
