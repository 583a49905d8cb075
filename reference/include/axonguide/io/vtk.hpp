#pragma once
// ParaView output: VTK XML PolyData (.vtp) files under DIR/vtk and DIR/growth.pvd.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "axonguide/engine/run.hpp"

namespace axg {

// Steps of the time series: 0, every output.frames_every, and the last step run.
std::vector<std::uint32_t> vtk_frame_steps(const RunResult& r);
// Writes the files and records their hashes in `info`. Needs r.paths (output.paths).
void write_vtk(const RunResult& r, const std::filesystem::path& dir, OutputInfo& info);

}  // namespace axg
