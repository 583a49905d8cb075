#include "axonguide/support/radix_sort.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "axonguide/core/cellgrid.hpp"

namespace axg {

namespace {
constexpr int kDigitBits = 11;
constexpr std::uint32_t kBuckets = 1u << kDigitBits;
}  // namespace

void stable_sort_by_key(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& values,
                        std::uint32_t max_key, SortScratch& scratch) {
  const std::size_t n = keys.size();
  scratch.chunks_used = 0;
  if (n < 2) return;
  const std::size_t chunk = std::max<std::size_t>(1, scratch.chunk);
  int passes = 0;
  for (std::uint64_t span = 1; span <= max_key; span <<= kDigitBits) ++passes;
  const std::size_t chunks = (n - 1) / chunk + 1;
  scratch.chunks_used = chunks;
  std::vector<std::uint32_t>& keys2 = scratch.keys;
  std::vector<std::uint32_t>& values2 = scratch.values;
  std::vector<std::uint32_t>& count = scratch.counts;
  keys2.resize(n);
  values2.resize(n);
  count.resize(chunks * kBuckets);
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = pass * kDigitBits;
    std::fill(count.begin(), count.end(), 0u);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      std::uint32_t* h = &count[c * kBuckets];
      const std::size_t end = std::min(n, (c + 1) * chunk);
      for (std::size_t i = c * chunk; i < end; ++i) ++h[(keys[i] >> shift) & (kBuckets - 1)];
    });
    // Exclusive scan in (digit, chunk) order: chunk c's items of a digit come after those
    // of chunks < c, which is what makes the pass stable.
    std::uint32_t sum = 0;
    for (std::uint32_t d = 0; d < kBuckets; ++d)
      for (std::size_t c = 0; c < chunks; ++c) {
        const std::uint32_t v = count[c * kBuckets + d];
        count[c * kBuckets + d] = sum;
        sum += v;
      }
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      std::uint32_t* h = &count[c * kBuckets];
      const std::size_t end = std::min(n, (c + 1) * chunk);
      for (std::size_t i = c * chunk; i < end; ++i) {
        const std::uint32_t pos = h[(keys[i] >> shift) & (kBuckets - 1)]++;
        keys2[pos] = keys[i];
        values2[pos] = values[i];
      }
    });
    keys.swap(keys2);
    values.swap(values2);
  }
}

void cell_starts(const std::vector<std::uint32_t>& sorted_keys, std::uint32_t num_cells,
                 std::vector<std::uint32_t>& start) {
  start.assign(static_cast<std::size_t>(num_cells) + 1, 0);
  const std::size_t n = sorted_keys.size();
  tbb::parallel_for(std::size_t{0}, n + 1, [&](std::size_t k) {
    core::fill_cell_starts(k, sorted_keys.data(), n, num_cells, start.data());
  });
}

}  // namespace axg
