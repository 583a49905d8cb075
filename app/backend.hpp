#pragma once
// --backend NAME: the accelerator library's require_backend and engine_factory (shared with
// the Python module).
#include "axonguide/accel/backend.hpp"

namespace axg::app {
using accel::engine_factory;
using accel::require_backend;
}  // namespace axg::app
