#pragma once
// The two builds of the pipeline (pipeline.inl), as seen by the dispatching code.
#include <memory>
#include <string>
#include <vector>

#include "axonguide/engine/engine.hpp"
#include "axonguide/graph/graph.hpp"

namespace axg::accel {

#define AXG_ACCEL_BACKEND_API                                                              \
  std::unique_ptr<Engine> make_engine(const Scene& scene, const Placement& placement);     \
  BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources);       \
  BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources);            \
  std::vector<std::uint32_t> components(const Csr& g);

namespace emu {
AXG_ACCEL_BACKEND_API
}

namespace gpu {
AXG_ACCEL_BACKEND_API
// Throws RunError (exit 3) with the CUDA error text when there is no usable device.
void require_device();
std::string device_description();
// Free and total device memory, bytes.
void device_memory(std::uint64_t* free_bytes, std::uint64_t* total_bytes);
}  // namespace gpu

}  // namespace axg::accel
