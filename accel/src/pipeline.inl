// The accelerator's pipeline, included by engine_cuda.cu (namespace gpu, Thrust's CUDA
// system) and engine_emulated.cpp (namespace emu, Thrust's sequential CPP system).
// Every kernel is a functor whose operator() handles one entity and calls core/
// functions; `launch` runs it once per index. Grids are built by a stable radix sort of
// (cell, id) (CUB's, through Thrust, on the GPU), compactions are stable (copy_if), and
// every floating-point sum is the one the core function performs, so the results equal
// the reference's bit for bit.
#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/device_vector.h>
#include <thrust/execution_policy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/host_vector.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/zip_iterator.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/tuple.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "axonguide/engine/cell_grid.hpp"
#include "axonguide/core/cellgrid.hpp"
#include "axonguide/core/estimate.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/core/signalling.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/engine/axon_stages.hpp"
#include "axonguide/engine/axon_step.hpp"
#include "axonguide/engine/engine.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/arbours.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/model/wander.hpp"
#include "axonguide/morphology/arbour.hpp"
#include "axonguide/morphology/arbour_step.hpp"
#include "axonguide/support/error.hpp"

// Files follow concepts: device (launch, atomics, sorted grids), growth, particles, grid
// field, graph, arbours, and the engine that strings them into steps.
#include "pipeline/device.inl"
#include "pipeline/growth.inl"
#include "pipeline/particles.inl"
#include "pipeline/grid_field.inl"
#include "pipeline/graph.inl"
#include "pipeline/arbours.inl"
#include "pipeline/engine.inl"
