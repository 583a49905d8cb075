#pragma once
// One growth step of one axon (SPEC §3.2, stages 3 and 4): move the tip by l*h and test
// contact, then bounds. A pure function of its arguments; the driver writes the result
// into the axon's own slot.
#include <cstdint>

#include "contact.hpp"
#include "hd.hpp"
#include "types.hpp"
#include "vec3.hpp"

namespace axg::core {

struct GrowthParams {
  double step_length;     // l0, length units per step (growth-rate modulation scales it per axon)
  double contact_radius;  // r_s + r_c, LU
  double contact_radius2; // its square, LU^2
  double bounds_radius;   // LU: ball radius, or half-edge when bounds_box
  bool bounds_box;
  ContactRule rule;
};

struct AxonStep {
  Vec3 tip;               // new tip (the contact point for a connection)
  double advanced;        // LU grown this step
  AxonStatus status;
  std::uint32_t target;   // kNoNeuron unless connected
};

// The tip starts on the soma surface: x = p + r_s h.
AXG_HDI Vec3 axon_start(Vec3 soma, Vec3 heading, double soma_radius) { return soma + soma_radius * heading; }

AXG_HDI bool outside_bounds(Vec3 p, const GrowthParams& g) {
  if (g.bounds_box) {
    const double r = g.bounds_radius;
    return p.x > r || p.x < -r || p.y > r || p.y < -r || p.z > r || p.z < -r;
  }
  return norm2(p) > g.bounds_radius * g.bounds_radius;
}

// Moves the tip by l h (l: this step's length).
AXG_HDI AxonStep grow_axon(std::uint32_t self, Vec3 tip, Vec3 heading, double l, const GrowthParams& g,
                           const CellGridView& somas) {
  const Vec3 s = l * heading;
  const Contact c = find_contact(self, tip, s, g.contact_radius, g.contact_radius2, g.rule, somas);
  if (c.target != kNoNeuron)
    return {tip + c.t * s, c.t * l, AxonStatus::kConnected, c.target};
  const Vec3 next = tip + s;
  if (outside_bounds(next, g)) return {next, l, AxonStatus::kExited, kNoNeuron};
  return {next, l, AxonStatus::kGrowing, kNoNeuron};
}

}  // namespace axg::core
