// The accelerator's pipeline on the GPU (Thrust's CUDA system: one thread per entity,
// CUB radix sorts), plus device discovery and error reporting.
#define AXG_ACCEL_NS gpu
#include <cuda_runtime.h>

#include <fmt/format.h>

#include "axonguide/error.hpp"
#include "backends.hpp"
#include "pipeline.inl"

namespace axg::accel::gpu {

namespace {
std::string cuda_error_text(cudaError_t e) {
  return fmt::format("{} ({})", cudaGetErrorString(e), cudaGetErrorName(e));
}
}  // namespace

void require_device() {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) throw RunError("--backend cuda: no usable GPU: " + cuda_error_text(e));
  if (count == 0) throw RunError("--backend cuda: no usable GPU: the CUDA runtime reports 0 devices");
  const cudaError_t s = cudaSetDevice(0);
  if (s != cudaSuccess) throw RunError("--backend cuda: cannot use GPU 0: " + cuda_error_text(s));
}

std::string device_description() {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count == 0) return "no usable GPU: " + (e != cudaSuccess ? cuda_error_text(e) : "0 devices");
  cudaDeviceProp p{};
  cudaGetDeviceProperties(&p, 0);
  return fmt::format("{}, compute {}.{}, {:.1f} GiB", p.name, p.major, p.minor,
                     static_cast<double>(p.totalGlobalMem) / (1024.0 * 1024.0 * 1024.0));
}

void device_memory(std::uint64_t* free_bytes, std::uint64_t* total_bytes) {
  std::size_t f = 0, t = 0;
  const cudaError_t e = cudaMemGetInfo(&f, &t);
  if (e != cudaSuccess) throw RunError("--backend cuda: cudaMemGetInfo failed: " + cuda_error_text(e));
  *free_bytes = f;
  *total_bytes = t;
}

}  // namespace axg::accel::gpu
