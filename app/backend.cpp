#include "backend.hpp"

#include "axonguide/error.hpp"
#if AXG_HAVE_CUDA
#include "axonguide/accel/cuda_engine.hpp"
#endif

namespace axg::app {

EngineFactory engine_factory(const std::string& backend) {
  if (backend == "reference") return {};
#if AXG_HAVE_CUDA
  if (backend == "cuda") return [](const Scene& s, const Placement& p) { return accel::make_cuda_engine(s, p); };
#else
  if (backend == "cuda")
    throw InputError(
        "--backend cuda: not built: this axonguide was configured without the CUDA accelerator "
        "(no nvcc was found); rebuild with the CUDA toolkit installed, or use --backend reference");
#endif
  throw InputError("--backend " + backend + ": must be reference or cuda");
}

}  // namespace axg::app
