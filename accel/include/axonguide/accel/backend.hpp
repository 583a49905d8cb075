#pragma once
// A backend by name ("reference", "cuda", "emulated"): what `axonguide run --backend` and
// the Python module's run(backend=) accept.
#include <string>

#include "axonguide/engine/run.hpp"

namespace axg::accel {
// Refuses backend NAME before any work is done: InputError (exit 2) for an unknown name
// or a CUDA engine that was not built ("not built"), RunError (exit 3) when the CUDA engine
// cannot run here ("no NVIDIA driver found", no device, a GPU of a compute capability the
// build has no code for). Call it before placement and before creating an output folder.
void require_backend(const std::string& backend);
// The engine factory for backend NAME, after require_backend(NAME); empty for the reference.
EngineFactory engine_factory(const std::string& backend);
}  // namespace axg::accel
