#include "backend.hpp"

#include "axonguide/accel/engines.hpp"
#include "axonguide/error.hpp"

namespace axg::app {

EngineFactory engine_factory(const std::string& backend) {
  if (backend == "reference") return {};
  if (backend == "cuda") {
    accel::require_cuda_built();  // refuse before placement, not after
    return [](const Scene& s, const Placement& p) { return accel::make_cuda_engine(s, p); };
  }
  throw InputError("--backend " + backend + ": must be reference or cuda");
}

}  // namespace axg::app
