// Dispatch between the builds, device checks and the device memory estimate.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <vector>

#include "axonguide/accel/engines.hpp"
#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"
#include "backends.hpp"

namespace axg::accel {

bool cuda_built() { return AXG_HAVE_CUDA_ENGINE != 0; }

void require_cuda_built() {
  if (!cuda_built())
    throw InputError(
        "--backend cuda: not built: this axonguide was configured without the CUDA accelerator (no nvcc was found); "
        "rebuild with the CUDA toolkit installed, or use --backend reference");
}

void require_cuda_device() {
  require_cuda_built();
#if AXG_HAVE_CUDA_ENGINE
  gpu::require_device();
#endif
}

std::string cuda_architectures() { return AXG_CUDA_ARCHITECTURES; }

std::string cuda_arch_refusal(int major, int minor, const std::string& archs) {
  const int device = major * 10 + minor;
  bool runs = false;
  std::vector<std::string> have;
  std::size_t begin = 0;
  while (begin <= archs.size()) {
    const std::size_t end = std::min(archs.find(',', begin), archs.size());
    std::string a = archs.substr(begin, end - begin);
    begin = end + 1;
    if (a.empty()) continue;
    bool sass = true, ptx = true;
    if (a.size() > 5 && a.compare(a.size() - 5, 5, "-real") == 0) ptx = false, a.resize(a.size() - 5);
    else if (a.size() > 8 && a.compare(a.size() - 8, 8, "-virtual") == 0) sass = false, a.resize(a.size() - 8);
    std::size_t digits = 0;
    while (digits < a.size() && a[digits] >= '0' && a[digits] <= '9') ++digits;
    const std::string suffix = a.substr(digits);
    if (digits < 2 || (suffix != "" && suffix != "a" && suffix != "f")) return {};  // native, all, all-major
    const int cc = std::stoi(a.substr(0, digits));
    const int cmaj = cc / 10, cmin = cc % 10;
    // sm_XYa and compute_XYa: X.Y only; sm_XYf and compute_XYf: the family X.Y to X.9.
    const bool exact = suffix == "a", family = suffix == "f";
    if (sass) {
      runs = runs || (exact ? device == cc : major == cmaj && minor >= cmin);
      have.push_back(fmt::format("sm_{} ({}.{}{})", a, cmaj, cmin, exact ? " only" : fmt::format(" to {}.9", cmaj)));
    }
    if (ptx) {
      runs = runs || (exact ? device == cc : family ? major == cmaj && minor >= cmin : device >= cc);
      have.push_back(fmt::format("PTX compute_{} ({}.{}{}, through the driver's JIT)", a, cmaj, cmin,
                                 exact ? " only" : family ? fmt::format(" to {}.9", cmaj) : " and newer"));
    }
  }
  if (runs || have.empty()) return {};
  std::string cmake_list = archs;
  std::replace(cmake_list.begin(), cmake_list.end(), ',', ';');
  return fmt::format(
      "compute capability {}.{}, which this build cannot run: it has code for {}; rebuild with "
      "-DCMAKE_CUDA_ARCHITECTURES=\"{}-real;{}\" or use --backend reference",
      major, minor, fmt::join(have, ", "), device, cmake_list);
}

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

#if AXG_HAVE_CUDA_ENGINE
std::unique_ptr<Engine> make_cuda_engine(const Scene& scene, const Placement& placement) {
  gpu::require_device();
  std::uint64_t free_bytes = 0, total_bytes = 0;
  gpu::device_memory(&free_bytes, &total_bytes);
  const std::uint64_t need = estimate_device_bytes(scene);
  if (need > free_bytes)
    throw RunError(fmt::format("--backend cuda: the scene needs an estimated {} of device memory; the GPU has {} free of {}",
                               human_bytes(static_cast<double>(need)), human_bytes(static_cast<double>(free_bytes)),
                               human_bytes(static_cast<double>(total_bytes))));
  return gpu::make_engine(scene, placement);
}
std::string cuda_device_description() { return gpu::device_description(); }
#else
std::unique_ptr<Engine> make_cuda_engine(const Scene&, const Placement&) {
  require_cuda_built();
  return nullptr;  // not reached
}
std::string cuda_device_description() { return "not built (no nvcc when axonguide was configured)"; }
#endif

std::string cuda_unavailable_reason() {
  if (!cuda_built()) return "the CUDA accelerator was not built (no nvcc at configure time)";
#if AXG_HAVE_CUDA_ENGINE
  try {
    gpu::require_device();
  } catch (const std::exception& e) {
    return e.what();
  }
#endif
  return {};
}

BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources, bool on_gpu) {
#if AXG_HAVE_CUDA_ENGINE
  if (on_gpu) {
    gpu::require_device();
    return gpu::bfs_level_sync(g, sources);
  }
#else
  if (on_gpu) require_cuda_built();
#endif
  return emu::bfs_level_sync(g, sources);
}

BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources, bool on_gpu) {
#if AXG_HAVE_CUDA_ENGINE
  if (on_gpu) {
    gpu::require_device();
    return gpu::bfs_queue(g, sources);
  }
#else
  if (on_gpu) require_cuda_built();
#endif
  return emu::bfs_queue(g, sources);
}

std::vector<std::uint32_t> components(const Csr& g, bool on_gpu) {
#if AXG_HAVE_CUDA_ENGINE
  if (on_gpu) {
    gpu::require_device();
    return gpu::components(g);
  }
#else
  if (on_gpu) require_cuda_built();
#endif
  return emu::components(g);
}

}  // namespace axg::accel
