#include "backend.hpp"

#include "axonguide/accel/engines.hpp"
#include "axonguide/error.hpp"

namespace axg::app {

EngineFactory engine_factory(const std::string& backend) {
  if (backend == "reference") return {};
  if (backend == "cuda") {
    if (!accel::cuda_built())
      throw InputError(
          "--backend cuda: not built: this axonguide was configured without the CUDA accelerator (no nvcc was found); "
          "rebuild with the CUDA toolkit installed, or use --backend reference");
    return [](const Scene& s, const Placement& p) { return accel::make_cuda_engine(s, p); };
  }
  throw InputError("--backend " + backend + ": must be reference or cuda");
}

}  // namespace axg::app
