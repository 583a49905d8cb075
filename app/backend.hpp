#pragma once
#include <string>

#include "axonguide/run.hpp"

namespace axg::app {
// Refuses --backend NAME before any work is done: InputError (exit 2) for an unknown name
// or a CUDA engine that was not built ("not built"), RunError (exit 3) when the CUDA engine
// cannot run here ("no NVIDIA driver found", no device, a GPU of a compute capability the
// build has no code for). Call it before placement and before creating an output folder.
void require_backend(const std::string& backend);
// The engine factory for --backend NAME, after require_backend(NAME).
EngineFactory engine_factory(const std::string& backend);
}  // namespace axg::app
