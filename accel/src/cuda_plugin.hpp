#pragma once
// The CUDA engine as a plugin (accel/CMakeLists.txt: libaxg_cuda.so, a MODULE). The command,
// the tests and the Python module load it with dlopen when a GPU is asked for
// (accel.cpp), so that building the command needs no nvcc and no CUDA compile. The plugin
// holds its own copy of the reference library and exports one symbol, axg_cuda_plugin(),
// which returns this table. The host refuses a plugin built from another commit, build
// type, compiler or flags (exit 2, naming both builds): its table and the objects it
// passes (Scene, Placement, Engine) would not be this build's.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "axonguide/engine/engine.hpp"
#include "axonguide/graph/graph.hpp"
#include "axonguide/version.hpp"

namespace axg::accel {

// Changes whenever CudaPlugin changes; read before any other field.
inline constexpr std::uint32_t kCudaPluginAbi = 1;

// What a build is: both sides must be the same one.
struct CudaBuild {
  const char* version;
  const char* commit;
  const char* build_type;
  const char* compiler;
  const char* cxx_flags;
  std::size_t scene_bytes;
  std::size_t placement_bytes;
};

inline CudaBuild this_build() {
  return {kVersion, kCommit, kBuildType, kCompiler, kCxxFlags, sizeof(Scene), sizeof(Placement)};
}

struct CudaPlugin {
  std::uint32_t abi;  // kCudaPluginAbi of the plugin's build
  CudaBuild build;
  const char* architectures;  // CMake's CUDA_ARCHITECTURES, comma-separated
  // The gpu:: functions of backends.hpp.
  void (*require_device)();
  std::string (*device_description)();
  void (*device_memory)(std::uint64_t* free_bytes, std::uint64_t* total_bytes);
  std::unique_ptr<Engine> (*make_engine)(const Scene& scene, const Placement& placement);
  BfsResult (*bfs_level_sync)(const Csr& g, const std::vector<std::uint32_t>& sources);
  BfsResult (*bfs_queue)(const Csr& g, const std::vector<std::uint32_t>& sources);
  std::vector<std::uint32_t> (*components)(const Csr& g);
};

}  // namespace axg::accel

// The plugin's one exported symbol.
extern "C" const axg::accel::CudaPlugin* axg_cuda_plugin();
