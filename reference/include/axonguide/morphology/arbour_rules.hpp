#pragma once
// The rules the arbour step follows (morphology/arbour_step.hpp), as the accelerator's
// kernels take them: trivially copyable, portable (no JSON, TBB or containers). The host
// derives them from the scene in model/arbours.cpp (ArbourParams::rules()).
#include <cstdint>

#include "axonguide/core/arbour.hpp"
#include "axonguide/core/branching.hpp"
#include "axonguide/core/hd.hpp"

namespace axg {

// What one neurite type's growth cones follow in a step (trivially copyable: the
// accelerator's kernels take it as it is; morphology/arbour_step.hpp applies it).
struct ConeRules {
  core::BranchingParams branching;
  core::ElongationParams elongation;
  core::ConeGeometry geometry;
  double stem_rate = 0.0;
  double lateral_rate = 0.0;  // per length unit per time unit
};
// What both neurite types share: the plane, the slab, the sample length and the soma rule
// (model/arbours.cpp reads them from the scene's `arbours` keys).
struct ArbourSettings {
  bool planar = false;
  double slab = 0.0;
  double sample_length = 0.0;
  bool stop_at_soma = true;
};
struct ArbourRules : ArbourSettings {
  ConeRules axon, dendrites;
  AXG_HD const ConeRules& of(std::uint8_t type) const { return type == 2 ? axon : dendrites; }  // SWC type 2: axon
};

}  // namespace axg
