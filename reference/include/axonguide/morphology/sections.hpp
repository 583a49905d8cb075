#pragma once
// An arbour's sections as NEURON numbers them when Import3d loads its SWC (docs/methods.md
// §2.13; checked by tests/python/test_synapse_clients.py), by Import3d's own rule
// (read_swc.hoc): a section is a run of samples in file order that ends at a sample with no
// child, several, one that is not the next in the file, or one of another type (a stem's
// first sample excepted: its other children join its section's start). Section 0 is the
// soma; then axon[i] is 1 + i and dend[j] follows the axon's sections. A section starts at
// its first sample's parent; one on the soma at its own first sample (a wire to the soma),
// unless that is its only sample, which Import3d joins to the soma's centre. Positions are
// arc length over the section's length, in [0, 1].
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/morphology/arbour.hpp"

namespace axg::morphology {

struct Sections {
  // By SWC sample id - 2: the sample's section, and the arc length from the section's start
  // to the sample.
  std::vector<std::uint32_t> section_of;
  std::vector<double> arc;
  std::vector<double> length;  // by section (the soma's: 0)
  // The 3-D point before each sample on its section's polyline, by id - 2, as Import3d's
  // index (0: the soma's centre; kNoPoint: the section's first 3-D point is the sample).
  // For the SWC axonguide writes it is the sample's parent.
  std::vector<std::uint32_t> previous;
  // Path length from the soma's surface (a stem's first sample) to each sample, by id - 2.
  std::vector<double> path;
};

Sections sections_of(const std::vector<ArbourSample>& samples, core::Vec3 soma);

// Where the point at parameter t along the segment that ends at `sample` (from its parent
// sample) lies: its section and position. The soma (sample 1): section 0, position 0.5.
struct SectionPoint {
  std::uint32_t section = 0;
  double pos = 0.5;
};
SectionPoint locate(const Sections& s, const std::vector<ArbourSample>& samples, std::uint32_t sample, double t);

}  // namespace axg::morphology
