// Dispatch between the builds, the CUDA plugin's loader, device checks and the device
// memory estimate.
#include <dlfcn.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <vector>

#include "axonguide/accel/engines.hpp"
#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"
#include "backends.hpp"
#include "cuda_plugin.hpp"

namespace axg::accel {

namespace {

namespace fs = std::filesystem;

// Where the plugin is looked for, in order: $AXG_CUDA_ENGINE (a path: nothing else is
// tried); beside the object this code is linked into, as bin/../lib/libaxg_cuda.so (the
// build tree's bin/ and tests/, an installed prefix, a bundle) or in its own folder; and
// the build tree's lib/ (the Python module, staged elsewhere).
std::vector<fs::path> plugin_candidates() {
  if (const char* p = std::getenv("AXG_CUDA_ENGINE"); p != nullptr && *p != '\0') return {fs::path(p)};
  std::vector<fs::path> out;
  const auto beside = [&out](const fs::path& object) {
    std::error_code ec;
    const fs::path self = fs::canonical(object, ec);
    if (ec) return;
    for (const fs::path& p : {self.parent_path().parent_path() / "lib" / "libaxg_cuda.so",
                              self.parent_path() / "libaxg_cuda.so"})
      if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  // dladdr names a shared object by its path; for the executable it may give argv[0].
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&plugin_candidates), &info) != 0 && info.dli_fname != nullptr &&
      std::strchr(info.dli_fname, '/') != nullptr)
    beside(fs::path(info.dli_fname));
  beside(fs::path("/proc/self/exe"));
  if (const fs::path built(AXG_CUDA_ENGINE_BUILD_PATH); std::find(out.begin(), out.end(), built) == out.end())
    out.push_back(built);
  return out;
}

std::string build_text(const CudaBuild& b) {
  return fmt::format("axonguide {} (commit {}, {}, {}, flags \"{}\", Scene {} B, Placement {} B)", b.version, b.commit,
                     b.build_type, b.compiler, b.cxx_flags, b.scene_bytes, b.placement_bytes);
}

bool same_build(const CudaBuild& a, const CudaBuild& b) {
  return std::strcmp(a.version, b.version) == 0 && std::strcmp(a.commit, b.commit) == 0 &&
         std::strcmp(a.build_type, b.build_type) == 0 && std::strcmp(a.compiler, b.compiler) == 0 &&
         std::strcmp(a.cxx_flags, b.cxx_flags) == 0 && a.scene_bytes == b.scene_bytes &&
         a.placement_bytes == b.placement_bytes;
}

// How to build the plugin, for the messages below.
std::string how_to_build() {
  return AXG_CUDA_CONFIGURED ? "build it with `cmake --build build --target axg_cuda` (the README's test command and "
                               "scripts/bundle.sh build it too)"
                             : "this build was configured without nvcc (no CUDA toolkit was found); install the CUDA "
                               "toolkit (/usr/local/cuda/bin/nvcc), then `cmake -S . -B build && cmake --build build "
                               "--target axg_cuda`";
}

struct Loaded {
  const CudaPlugin* api = nullptr;
  std::string refusal;  // why there is none (InputError, exit 2)
};

Loaded load_plugin() {
  const std::vector<fs::path> candidates = plugin_candidates();
  std::string looked;
  for (const fs::path& path : candidates) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      looked += (looked.empty() ? "" : ", ") + path.string();
      continue;
    }
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();
      return {nullptr, fmt::format("--backend cuda: the CUDA engine {} cannot be loaded ({}); {}", path.string(),
                                   why ? why : "dlopen failed", how_to_build())};
    }
    using Entry = const CudaPlugin* (*)();
    const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "axg_cuda_plugin"));
    const CudaPlugin* api = entry ? entry() : nullptr;
    if (api == nullptr)
      return {nullptr, fmt::format("--backend cuda: {} is not an axonguide CUDA engine (no axg_cuda_plugin); {}",
                                   path.string(), how_to_build())};
    if (api->abi != kCudaPluginAbi)
      return {nullptr, fmt::format("--backend cuda: the CUDA engine {} has plugin interface {}, this axonguide {} ({}); "
                                   "rebuild it: {}",
                                   path.string(), api->abi, kCudaPluginAbi, build_text(this_build()), how_to_build())};
    if (!same_build(api->build, this_build()))
      return {nullptr, fmt::format("--backend cuda: the CUDA engine {} was built as {}, but this command is {}: they "
                                   "must be one build; rebuild it: {}",
                                   path.string(), build_text(api->build), build_text(this_build()), how_to_build())};
    return {api, {}};  // never closed: its engines live until exit
  }
  return {nullptr, fmt::format("--backend cuda: the CUDA engine is not built (no libaxg_cuda.so at {}); {}", looked,
                               how_to_build())};
}

// Loaded at most once per process, on the first use of a GPU.
const Loaded& plugin() {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = load_plugin(); });
  return loaded;
}

// The plugin's table, or InputError (exit 2) saying why there is none.
const CudaPlugin& gpu_api() {
  const Loaded& p = plugin();
  if (p.api == nullptr) throw InputError(p.refusal);
  return *p.api;
}

}  // namespace

bool cuda_configured() { return AXG_CUDA_CONFIGURED != 0; }

bool cuda_built() { return plugin().api != nullptr; }

std::string cuda_refusal() { return plugin().refusal; }

void require_cuda_built() { gpu_api(); }

void require_cuda_device() { gpu_api().require_device(); }

std::string cuda_architectures() { return cuda_built() ? gpu_api().architectures : ""; }

std::uint64_t estimate_device_bytes(const Scene& scene) {
  const double n = static_cast<double>(scene.neurons.count);
  // ids, soma keys/starts, sorted positions, tip, heading, length, status, steps,
  // target (slot and id order), two active lists, download scratch.
  double bytes = n * (4 + 8 + 24 + 24 + 24 + 8 + 1 + 4 + 4 + 4 + 8 + 24);
  // Arbours: pools at up to twice what they hold (point 36 B; a cone and its entries under
  // 80 B, at most one per point), and a second copy while they grow.
  if (scene.arbours) bytes += n * expected_arbour_points(scene) * 2.0 * (36.0 + 80.0) * 2.0;
  if (scene.uses_cues()) {
    if (scene.cues.field == FieldKind::kParticles) {
      // position, velocity, id, source, keep, scratch copies, keys, index, sorted copies
      bytes += expected_particles(scene) * (24 * 2 + 8 * 2 + 2 * 2 + 1 + 24 * 2 + 4 * 2 + 24 + 2) * 1.5;
      bytes += static_cast<double>(particle_hash_geometry(scene).buckets()) * 4;
    } else if (scene.cues.field == FieldKind::kGrid) {
      const double nodes = static_cast<double>(grid_field_geometry(scene).nodes());
      bytes += nodes * 8 * (scene.source_count() * (scene.cues.grid.scheme == GridScheme::kExplicit ? 2.0 : 1.0) + 2.0);
    }
  }
  return bytes >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
}

std::unique_ptr<Engine> make_emulated_engine(const Scene& scene, const Placement& placement) {
  return emu::make_engine(scene, placement);
}

std::unique_ptr<Engine> make_cuda_engine(const Scene& scene, const Placement& placement) {
  const CudaPlugin& gpu = gpu_api();
  gpu.require_device();
  std::uint64_t free_bytes = 0, total_bytes = 0;
  gpu.device_memory(&free_bytes, &total_bytes);
  const std::uint64_t need = estimate_device_bytes(scene);
  if (need > free_bytes)
    throw RunError(fmt::format("--backend cuda: the scene needs an estimated {} of device memory; the GPU has {} free of {}",
                               human_bytes(static_cast<double>(need)), human_bytes(static_cast<double>(free_bytes)),
                               human_bytes(static_cast<double>(total_bytes))));
  return gpu.make_engine(scene, placement);
}

std::string cuda_device_description() {
  if (!cuda_built()) return "not built: " + cuda_refusal();
  return gpu_api().device_description();
}

std::string cuda_unavailable_reason() {
  if (!cuda_built()) return cuda_refusal();
  try {
    gpu_api().require_device();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources, bool on_gpu) {
  if (on_gpu) {
    require_cuda_device();
    return gpu_api().bfs_level_sync(g, sources);
  }
  return emu::bfs_level_sync(g, sources);
}

BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources, bool on_gpu) {
  if (on_gpu) {
    require_cuda_device();
    return gpu_api().bfs_queue(g, sources);
  }
  return emu::bfs_queue(g, sources);
}

std::vector<std::uint32_t> components(const Csr& g, bool on_gpu) {
  if (on_gpu) {
    require_cuda_device();
    return gpu_api().components(g);
  }
  return emu::components(g);
}

}  // namespace axg::accel
