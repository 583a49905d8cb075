#pragma once
// Stable LSD radix sort of (key, value) pairs by key, parallel with TBB. The result of a
// stable sort is unique, so it does not depend on how the work is split among threads:
// this is how every grid in the reference is built (hash, stable sort by cell, then cell
// start/end), mirroring CUB's radix sort in the accelerator.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace axg {

// Keys per histogram chunk: a sort of more keys counts and scatters its chunks in parallel.
inline constexpr std::size_t kRadixSortChunk = std::size_t{1} << 16;

// Scratch of a sort, kept by callers that sort every step.
struct SortScratch {
  std::vector<std::uint32_t> keys, values, counts;
  // Keys per histogram chunk. Only tests change it (to sort many keys in one chunk): the
  // result does not depend on it.
  std::size_t chunk = kRadixSortChunk;
  std::size_t chunks_used = 0;  // chunks of the last sort (0 when it had fewer than 2 keys)
};

// Sorts keys ascending, carrying values along; equal keys keep their input order.
// max_key bounds the keys (it sets the number of 11-bit passes).
void stable_sort_by_key(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& values,
                        std::uint32_t max_key, SortScratch& scratch);
inline void stable_sort_by_key(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& values,
                               std::uint32_t max_key) {
  SortScratch scratch;
  stable_sort_by_key(keys, values, max_key, scratch);
}

// start[c] = first index of key c in the sorted keys, start[num_cells] = keys.size().
void cell_starts(const std::vector<std::uint32_t>& sorted_keys, std::uint32_t num_cells,
                 std::vector<std::uint32_t>& start);

}  // namespace axg
