#pragma once
// The one host/device marker of the portable core. Everything in core/ is header-only,
// free of containers, TBB and I/O, and callable unchanged from a CUDA kernel.
#include <cstdint>
#include <cstring>

#if defined(__CUDACC__)
#define AXG_HD __host__ __device__
#else
#define AXG_HD
#endif
#define AXG_HDI AXG_HD inline
// For the few hot helpers that the compiler declines to inline on its own (measured: the
// Rng's block buffer stays in registers only when its user is inlined).
#if defined(__CUDACC__)
#define AXG_HDFI __host__ __device__ __forceinline__
#elif defined(__GNUC__)
#define AXG_HDFI inline __attribute__((always_inline))
#else
#define AXG_HDFI inline
#endif

namespace axg::core {

AXG_HDI std::uint64_t bits_of(double x) {
#if defined(__CUDA_ARCH__)
  return static_cast<std::uint64_t>(__double_as_longlong(x));
#else
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
#endif
}

AXG_HDI double double_of(std::uint64_t u) {
#if defined(__CUDA_ARCH__)
  return __longlong_as_double(static_cast<long long>(u));
#else
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
#endif
}

}  // namespace axg::core
