#pragma once
// The stream table: every random number in axonguide is Philox4x32-10 of
//
//   key     = { seed & 0xffffffff, seed >> 32 }                    (the 64-bit scene seed)
//   counter = { tag | (id >> 32) << 8,  id & 0xffffffff,  step,  block }
//
// tag   (8 bits)  : the stream, from the table below; never reused for another purpose;
// id    (56 bits) : the entity (neuron, particle, source, validation point);
// step  (32 bits) : the time step, or the attempt number for placement;
// block (32 bits) : the draw index, counted in Philox blocks of 4 x 32 bits.
//
// A block gives two doubles (two 32-bit words each). A random number is therefore a pure
// function of (seed, tag, id, step, draw index): no engine state, no per-thread
// generator, identical on host and device. Doubles come from exact integer formulas:
//   u01_open(w)        = (2k+1) / 2^53 with k = w >> 12   in (0,1), 52-bit grid, symmetric
//   u01_closed_open(w) = k / 2^53      with k = w >> 11   in [0,1), 53-bit grid
// Both are exact: the integer fits the 53-bit significand and the scale is a power of 2.
#include <Random123/philox.h>

#include "hd.hpp"

namespace axg::core {

// Stream tags. Append only: changing a value changes every result that uses it.
enum class Stream : std::uint32_t {
  kPlacement = 1,         // id = neuron, step = attempt: soma position
  kAxonDirection = 2,     // id = neuron, step = 0: initial heading
  kSourcePosition = 3,    // id = source index, step = 0: sampled cue source position
  kParticleEmission = 4,  // id = particle id, step = birth step: offset and velocity at birth
  kParticleMotion = 5,    // id = particle id, step = step: Brownian increment, then the survival draw
  kParticleDecay = 6,     // retired (survival now follows the motion draws of kParticleMotion)
  kSteerDecision = 7,     // id = neuron, step = the decision's interval (per_step: the step): X ~ N(|E|, 1)
  kSteerPerpendicular = 8,// id = neuron, step = the decision's interval: the side when the evidence has none
  kValidation = 9,        // id = point index, step = test index: validation harness
  kBenchmark = 10,        // id = point index: benchmarks
  kSourceKind = 11,       // id = source index: attractant or repellent for random_sources
  kWander = 12,           // id = neuron, step = step: the axis of the heading's random walk
  kBranch = 13,           // id = growth cone (core::cone_key), step = step: does the cone branch
  kConeWander = 14,       // id = growth cone, step = step: the axis (or side) of its heading's random walk
  kConeBirth = 15,        // id = growth cone, step = 0: its elongation-rate factor, stem heading and height
  kConeSplit = 16,        // id = growth cone, step = step: the angle and plane between its daughters
  kStems = 17,            // id = neuron, step = step (0: birth): how many stems start (axons, dendrites)
  kLateral = 18,          // id = neuron, step = step: how many lateral branches start, and where (axons, dendrites)
  kSynapse = 19,          // id = pre | post_sample << 32, step = post, block = pre_sample: is an apposition realised
};

struct Counter {
  std::uint32_t tag_id_hi;
  std::uint32_t id_lo;
  std::uint32_t step;
};

AXG_HDI Counter make_counter(Stream tag, std::uint64_t id, std::uint32_t step) {
  return Counter{static_cast<std::uint32_t>(tag) | static_cast<std::uint32_t>((id >> 32) << 8),
                 static_cast<std::uint32_t>(id & 0xffffffffu), step};
}

// One Philox4x32-10 block.
AXG_HDI r123::Philox4x32::ctr_type philox_block(std::uint64_t seed, Counter c,
                                                std::uint32_t block) {
  r123::Philox4x32 rng;
  r123::Philox4x32::key_type key = {{static_cast<std::uint32_t>(seed & 0xffffffffu),
                                     static_cast<std::uint32_t>(seed >> 32)}};
  r123::Philox4x32::ctr_type ctr = {{c.tag_id_hi, c.id_lo, c.step, block}};
  return rng(ctr, key);
}

AXG_HDI std::uint64_t join64(std::uint32_t hi, std::uint32_t lo) {
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

// (2k+1)/2^53, k = w >> 12: in (0,1), never 0 or 1, exact.
AXG_HDI double u01_open(std::uint64_t w) {
  return static_cast<double>(((w >> 12) << 1) | 1u) * 0x1p-53;
}

// k/2^53, k = w >> 11: in [0,1), exact.
AXG_HDI double u01_closed_open(std::uint64_t w) {
  return static_cast<double>(w >> 11) * 0x1p-53;
}

// Sequential draws from one (seed, tag, id, step) stream. It holds a block buffer while a
// function runs; it is never stored between steps, so it is not an engine: the n-th draw
// is always the same function of the stream's coordinates.
class Rng {
 public:
  AXG_HD Rng(std::uint64_t seed, Stream tag, std::uint64_t id, std::uint32_t step,
             std::uint32_t first_block = 0)
      : seed_(seed), ctr_(make_counter(tag, id, step)), block_(first_block) {}

  // Uniform in (0,1) (52-bit grid). Safe for log().
  AXG_HD double uniform() { return u01_open(next_word64()); }
  // Uniform in [0,1) (53-bit grid).
  AXG_HD double uniform_co() { return u01_closed_open(next_word64()); }
  // Uniform in (-1,1), exact: 2u - 1 with u on the (2k+1)/2^53 grid.
  AXG_HD double symmetric() { return 2.0 * uniform() - 1.0; }
  AXG_HD std::uint32_t word32() {
    if (used_ == 4) refill();
    return buf_[used_++];
  }
  AXG_HD std::uint32_t blocks_used() const { return block_; }

 private:
  AXG_HD void refill() {
    auto r = philox_block(seed_, ctr_, block_++);
    for (int k = 0; k < 4; ++k) buf_[k] = r.v[k];
    used_ = 0;
  }
  AXG_HD std::uint64_t next_word64() {
    if (used_ > 2) refill();
    std::uint64_t w = join64(buf_[used_], buf_[used_ + 1]);
    used_ += 2;
    return w;
  }

  std::uint64_t seed_;
  Counter ctr_;
  std::uint32_t block_;
  std::uint32_t buf_[4] = {0, 0, 0, 0};
  int used_ = 4;
};

}  // namespace axg::core
