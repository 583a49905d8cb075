#include "axonguide/accel/backend.hpp"

#include "axonguide/accel/engines.hpp"
#include "axonguide/support/error.hpp"

namespace axg::accel {

void require_backend(const std::string& backend) {
  if (backend == "reference" || backend == "emulated") return;
  if (backend == "cuda") return require_cuda_device();
  throw InputError("--backend " + backend + ": must be reference, cuda or emulated");
}

EngineFactory engine_factory(const std::string& backend) {
  require_backend(backend);  // refuse before placement, not after
  if (backend == "cuda")
    return [](const Scene& s, const Placement& p) { return make_cuda_engine(s, p); };
  // The accelerator's pipeline compiled for the CPU (slow; for checks such as resume).
  if (backend == "emulated")
    return [](const Scene& s, const Placement& p) { return make_emulated_engine(s, p); };
  return {};
}

}  // namespace axg::accel
