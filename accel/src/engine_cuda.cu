// The accelerator's pipeline on the GPU (Thrust's CUDA system: one thread per entity,
// CUB radix sorts), plus device discovery and error reporting: the CUDA plugin
// (libaxg_cuda.so; its table in cuda_plugin.hpp).
#define AXG_ACCEL_NS gpu
#include <cuda_runtime.h>
#include <dlfcn.h>

#include <cstdlib>

#include <fmt/format.h>

#include "axonguide/accel/engines.hpp"
#include "axonguide/support/error.hpp"
#include "backends.hpp"
#include "cuda_plugin.hpp"
#include "pipeline.inl"

namespace axg::accel::gpu {

namespace {
std::string cuda_error_text(cudaError_t e) {
  return fmt::format("{} ({})", cudaGetErrorString(e), cudaGetErrorName(e));
}

// "13.0" from 13000 (cudaDriverGetVersion, CUDART_VERSION).
std::string cuda_version_text(int v) { return fmt::format("{}.{}", v / 1000, v % 1000 / 10); }

// Has no body: loading it tells whether the fat binary holds code this GPU can run.
__global__ void probe_kernel() {}
}  // namespace

// In order: the driver library, the driver's CUDA version, a device, its compute
// capability against the architectures built, and the kernels actually loading on it.
void require_device() {
  // The static runtime loads the driver library itself, and says only "CUDA driver version
  // is insufficient" when there is none; looking for it first gives the plain reason.
  if (::dlopen("libcuda.so.1", RTLD_LAZY | RTLD_LOCAL) == nullptr) {
    const char* why = ::dlerror();
    throw RunError(fmt::format("--backend cuda: no NVIDIA driver found ({}), so no GPU can be used here; use "
                               "--backend reference",
                               why ? why : "libcuda.so.1 not found"));
  }
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e == cudaErrorInsufficientDriver) {
    int driver = 0;
    cudaDriverGetVersion(&driver);
    if (driver == 0)
      throw RunError("--backend cuda: no NVIDIA driver found (libcuda.so.1 loads but reports no driver); use "
                     "--backend reference");
    throw RunError(fmt::format("--backend cuda: the NVIDIA driver supports CUDA {}, older than this build's runtime "
                               "(CUDA {}): update the driver, or use --backend reference",
                               cuda_version_text(driver), cuda_version_text(CUDART_VERSION)));
  }
  if (e == cudaErrorNoDevice)
    throw RunError("--backend cuda: no usable GPU: the NVIDIA driver is loaded but reports no device" +
                   std::string(std::getenv("CUDA_VISIBLE_DEVICES") ? fmt::format(" (CUDA_VISIBLE_DEVICES={})",
                                                                                 std::getenv("CUDA_VISIBLE_DEVICES"))
                                                                   : ""));
  if (e != cudaSuccess) throw RunError("--backend cuda: no usable GPU: " + cuda_error_text(e));
  if (count == 0) throw RunError("--backend cuda: no usable GPU: the CUDA runtime reports 0 devices");
  cudaDeviceProp p{};
  const cudaError_t q = cudaGetDeviceProperties(&p, 0);
  if (q != cudaSuccess) throw RunError("--backend cuda: cannot query GPU 0: " + cuda_error_text(q));
  if (const std::string why = cuda_arch_refusal(p.major, p.minor, AXG_CUDA_ARCHITECTURES); !why.empty())
    throw RunError(fmt::format("--backend cuda: GPU 0 ({}) has {}", p.name, why));
  const cudaError_t s = cudaSetDevice(0);
  if (s != cudaSuccess) throw RunError("--backend cuda: cannot use GPU 0: " + cuda_error_text(s));
  cudaFuncAttributes attr{};
  const cudaError_t k = cudaFuncGetAttributes(&attr, probe_kernel);
  if (k != cudaSuccess)
    throw RunError(fmt::format("--backend cuda: GPU 0 ({}, compute capability {}.{}) cannot load this build's kernels "
                               "(built for {}): {}; rebuild with -DCMAKE_CUDA_ARCHITECTURES={}{}, or use --backend "
                               "reference",
                               p.name, p.major, p.minor, AXG_CUDA_ARCHITECTURES, cuda_error_text(k), p.major, p.minor));
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

extern "C" __attribute__((visibility("default"))) const axg::accel::CudaPlugin* axg_cuda_plugin() {
  namespace gpu = axg::accel::gpu;
  static const axg::accel::CudaPlugin table{axg::accel::kCudaPluginAbi,
                                            axg::accel::this_build(),
                                            AXG_CUDA_ARCHITECTURES,
                                            gpu::require_device,
                                            gpu::device_description,
                                            gpu::device_memory,
                                            gpu::make_engine,
                                            gpu::bfs_level_sync,
                                            gpu::bfs_queue,
                                            gpu::components};
  return &table;
}
