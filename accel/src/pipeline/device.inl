// Device vectors, the launch of one functor per index, the integer atomics, and the
// sorted grids (hash, stable sort by key, cell starts, gathers) every stage builds on.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

using core::Vec3;
template <class T>
using dvec = thrust::device_vector<T>;

template <class T>
T* raw(dvec<T>& v) {
  return thrust::raw_pointer_cast(v.data());
}
template <class T>
const T* raw(const dvec<T>& v) {
  return thrust::raw_pointer_cast(v.data());
}

// One call of f(i) for every i in [0, n): a grid of threads on the GPU, a loop on the CPU.
template <class F>
void launch(std::size_t n, const F& f) {
  if (n == 0) return;
  thrust::for_each_n(thrust::device, thrust::counting_iterator<std::size_t>(0), n, f);
}

// ---- Integer atomics (the only atomics: their results do not depend on order). ----

AXG_HDI int atomic_cas(int* p, int expected, int desired) {
#if defined(__CUDA_ARCH__)
  return atomicCAS(p, expected, desired);
#else
  const int old = *p;
  if (old == expected) *p = desired;
  return old;
#endif
}

AXG_HDI void atomic_min(std::uint32_t* p, std::uint32_t v) {
#if defined(__CUDA_ARCH__)
  atomicMin(reinterpret_cast<unsigned int*>(p), static_cast<unsigned int>(v));
#else
  if (v < *p) *p = v;
#endif
}

AXG_HDI std::uint32_t atomic_add(std::uint32_t* p, std::uint32_t v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(reinterpret_cast<unsigned int*>(p), static_cast<unsigned int>(v));
#else
  const std::uint32_t old = *p;
  *p = old + v;
  return old;
#endif
}

AXG_HDI void atomic_add(std::uint64_t* p, std::uint64_t v) {
#if defined(__CUDA_ARCH__)
  atomicAdd(reinterpret_cast<unsigned long long*>(p), static_cast<unsigned long long>(v));
#else
  *p = *p + v;
#endif
}

// ---- Grids: hash, stable sort by key, cell starts, sorted copies. ----

struct FillCellStarts {
  const std::uint32_t* d_keys;
  std::size_t n;
  std::uint32_t cells;
  std::uint32_t* d_start;
  AXG_HD void operator()(std::size_t k) const { core::fill_cell_starts(k, d_keys, n, cells, d_start); }
};

struct SomaKeys {
  const Vec3* d_pos;
  core::CellGridView geometry;
  std::uint32_t* d_keys;
  std::uint32_t* d_ids;
  AXG_HD void operator()(std::size_t i) const {
    d_keys[i] = core::cell_of(d_pos[i], geometry);
    d_ids[i] = static_cast<std::uint32_t>(i);
  }
};

template <class T>
struct GatherBy {
  const T* d_in;
  const std::uint32_t* d_index;
  T* d_out;
  AXG_HD void operator()(std::size_t k) const { d_out[k] = d_in[d_index[k]]; }
};

template <class T>
struct ScatterBy {
  const T* d_in;
  const std::uint32_t* d_index;
  T* d_out;
  AXG_HD void operator()(std::size_t k) const { d_out[d_index[k]] = d_in[k]; }
};

// keys are sorted stably (values carried), then cell starts are found.
inline void sort_and_find_starts(dvec<std::uint32_t>& keys, dvec<std::uint32_t>& values, std::uint32_t cells,
                                 dvec<std::uint32_t>& start) {
  thrust::stable_sort_by_key(thrust::device, keys.begin(), keys.end(), values.begin());
  start.resize(static_cast<std::size_t>(cells) + 1);
  launch(keys.size() + 1, FillCellStarts{raw(keys), keys.size(), cells, raw(start)});
}

}  // namespace axg::accel::AXG_ACCEL_NS
