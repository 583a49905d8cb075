#pragma once
// Stable parallel compaction: keep[i] selects element i; survivors keep their order.
// Offsets come from per-chunk counts and a scan in chunk order, so the result does not
// depend on the thread count.
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

namespace axg {

class StableCompaction {
 public:
  static constexpr std::size_t kChunk = 1u << 14;

  // Counts survivors per chunk; returns their total.
  std::size_t plan(const std::vector<std::uint8_t>& keep) {
    n_ = keep.size();
    const std::size_t chunks = (n_ + kChunk - 1) / kChunk;
    offset_.assign(chunks + 1, 0);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      std::size_t k = 0;
      for (std::size_t i = c * kChunk, e = std::min(n_, (c + 1) * kChunk); i < e; ++i) k += keep[i];
      offset_[c + 1] = k;
    });
    for (std::size_t c = 0; c < chunks; ++c) offset_[c + 1] += offset_[c];
    keep_ = &keep;
    return offset_.back();
  }

  // Applies the plan to one array; `scratch` receives the survivors and is swapped in
  // (callers keep it between steps, so that no step allocates).
  template <class T>
  void apply(std::vector<T>& v, std::vector<T>& scratch) const {
    std::vector<T>& out = scratch;
    out.resize(offset_.back());
    const std::size_t chunks = offset_.size() - 1;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      std::size_t o = offset_[c];
      for (std::size_t i = c * kChunk, e = std::min(n_, (c + 1) * kChunk); i < e; ++i)
        if ((*keep_)[i]) out[o++] = v[i];
    });
    v.swap(out);
  }

 private:
  std::size_t n_ = 0;
  std::vector<std::size_t> offset_;
  const std::vector<std::uint8_t>* keep_ = nullptr;
};

}  // namespace axg
