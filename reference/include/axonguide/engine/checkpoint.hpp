#pragma once
// Checkpoints (SPEC §4): the state of a run between two steps, written atomically into
// the run's folder and read back by `axonguide run --resume`. A checkpoint holds the
// version and commit that wrote it, the SHA-256 of the canonical scene, the step, what
// the run has recorded so far (somas, stats, paths, particle frames, timings) and the
// engine's state in id order; its last 64 bytes are the hex SHA-256 of the rest.
#include <cstdint>
#include <filesystem>
#include <string>

#include "axonguide/engine/run.hpp"
#include "axonguide/engine/state.hpp"

namespace axg {

inline constexpr const char* kCheckpointName = "checkpoint.axg";

// Hex SHA-256 of the scene's canonical JSON (seed included): what a checkpoint and a
// resume compare.
std::string scene_hash(const Scene& scene);

struct RunCheckpoint {
  std::uint32_t step = 0;  // steps run when it was written
  std::string version, commit, scene_hash;
  RunResult progress;      // soma, placement_redraws, stats, paths, frames, times, steps_run
  EngineState engine;
};

// Writes DIR/checkpoint.axg atomically (temporary name, fsync, rename); returns its
// size in bytes. Throws RunError on I/O failure.
std::uint64_t write_checkpoint(const std::filesystem::path& dir, const RunResult& progress, std::uint32_t step,
                               const EngineState& engine);

// Reads and checks a checkpoint (format, byte order, the trailing SHA-256). Throws
// RunError when the file is unreadable, truncated or fails its hash.
RunCheckpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace axg
