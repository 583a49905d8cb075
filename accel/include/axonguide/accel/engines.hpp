#pragma once
// The accelerator: the per-step pipeline of the reference, written once against Thrust
// (kernels are functors that call core/ functions) and built twice:
// - on the GPU (nvcc, Thrust's CUDA system: CUB radix sorts, one thread per entity);
// - on the CPU (g++, Thrust's sequential CPP system): the same kernels, launched by a host
//   loop, so that CI checks the pipeline's logic byte for byte without a GPU.
#include <memory>
#include <string>
#include <vector>

#include "axonguide/engine/engine.hpp"
#include "axonguide/graph/graph.hpp"

namespace axg::accel {

// The CUDA engine is a plugin, libaxg_cuda.so (accel/src/cuda_plugin.hpp), built by
// `cmake --build build --target axg_cuda` when nvcc was found at configure time, and
// loaded on the first use of a GPU.
// True when nvcc was found when this build was configured (the plugin's target exists).
bool cuda_configured();
// True when the CUDA plugin was found, loads, and is this build's (same commit, build
// type, compiler and flags).
bool cuda_built();
// Why there is no CUDA engine (not built, with how to build it; cannot be loaded; from
// another build, naming both); empty when cuda_built().
std::string cuda_refusal();
// Throws InputError (exit 2) with cuda_refusal() when !cuda_built().
void require_cuda_built();
// Throws InputError (exit 2) when the CUDA engine is not built or not this build's, and
// RunError (exit 3) when it cannot run here: "no NVIDIA driver found" (libcuda.so.1
// absent), a driver older than the runtime, no device, or a GPU whose compute capability
// the build has no code for (naming both).
void require_cuda_device();

// CMake's CUDA_ARCHITECTURES of the CUDA plugin, comma-separated ("90-real,90-virtual");
// empty when there is none.
std::string cuda_architectures();
// Empty when code built for `archs` (as above) runs on a GPU of compute capability
// major.minor; otherwise why not, naming the compute capability. SASS sm_XY runs on X.Y
// to X.9 (sm_XYa on X.Y only); PTX compute_XY on X.Y and newer, through the driver's JIT.
// Lists CMake resolves itself (native, all, all-major) are not judged here: empty.
std::string cuda_arch_refusal(int major, int minor, const std::string& archs);

// The CUDA engine. Throws InputError when it was not built (exit 2) and RunError (exit
// 3) when no usable GPU is present (with the CUDA error text) or when the scene's device
// memory estimate exceeds the GPU's free memory.
std::unique_ptr<Engine> make_cuda_engine(const Scene& scene, const Placement& placement);
// "NVIDIA H100 80GB HBM3, compute 9.0, 79.1 GiB" or the reason there is none.
std::string cuda_device_description();
// Empty when the CUDA engine can run here; otherwise why not (not built, or the CUDA
// error text). Tests and `validate gpu` report it when they skip.
std::string cuda_unavailable_reason();

// The same pipeline on the CPU (Thrust's sequential host system).
std::unique_ptr<Engine> make_emulated_engine(const Scene& scene, const Placement& placement);

// The graph kernels on their own (for tests and benchmarks): the report's level-
// synchronous BFS (one thread per vertex), the work-efficient queue-based BFS, and
// components by min-label propagation. `gpu` selects the CUDA build.
BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources, bool gpu);
BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources, bool gpu);
std::vector<std::uint32_t> components(const Csr& g, bool gpu);

// Device bytes the accelerator needs for the scene (estimated before allocation).
std::uint64_t estimate_device_bytes(const Scene& scene);

}  // namespace axg::accel
