#pragma once
#include <string>

#include "axonguide/run.hpp"

namespace axg::app {
// The engine factory for --backend NAME; throws InputError when it was not built.
EngineFactory engine_factory(const std::string& backend);
}  // namespace axg::app
