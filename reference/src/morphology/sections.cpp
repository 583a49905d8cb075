// NEURON's sections of an arbour (docs/methods.md §2.13): Import3d's own rule
// (share/nrn/lib/hoc/import3d/read_swc.hoc: mark_branch, sectionify, mksection) applied to
// the SWC as axonguide writes it (a one-point soma, sample 1; every parent listed first).
#include "axonguide/morphology/sections.hpp"

#include <algorithm>
#include <cmath>

namespace axg::morphology {

Sections sections_of(const std::vector<ArbourSample>& s, core::Vec3 soma) {
  // Points by Import3d's index: 0 the soma, i the sample i + 1.
  const std::size_t n = s.size() + 1;
  auto type = [&](std::size_t i) { return i == 0 ? std::uint8_t{1} : s[i - 1].type; };
  auto parent = [&](std::size_t i) { return static_cast<std::size_t>(s[i - 1].parent - 1); };
  auto point = [&](std::size_t i) { return i == 0 ? soma : s[i - 1].pos; };
  // mark_branch, in hundredths: each child adds 1, a child not next in the file 0.01 more
  // (but a stem's first point keeps 1: its other children join its section's proximal
  // end), and a child of another type 0.01 more. A point whose count is not 1 ends a section.
  std::vector<int> count(n, 0);
  for (std::size_t i = 1; i < n; ++i) {
    const std::size_t p = parent(i);
    count[p] += 100;
    if (p != i - 1) {
      count[p] += 1;
      if (p > 1 && type(p) != 1 && type(parent(p)) == 1) count[p] = 100;
    }
    if (type(p) != type(i)) count[p] += 1;
  }
  Sections out;
  out.section_of.assign(s.size(), 0);
  out.arc.assign(s.size(), 0.0);
  out.previous.assign(s.size(), kNoPoint);
  out.path.assign(s.size(), 0.0);
  for (std::size_t k = 0; k < s.size(); ++k)
    out.path[k] = s[k].parent == 1 ? 0.0 : out.path[s[k].parent - 2] + core::norm(s[k].pos - s[s[k].parent - 2].pos);
  // Sections: runs of points in file order, each ending at a point whose count is not 1;
  // section 0 is the soma's.
  struct Run {
    std::size_t first, end;
  };
  std::vector<Run> runs;
  std::size_t first = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (count[i] != 100) {
      runs.push_back({first, i});
      first = i + 1;
    }
  // Names: soma[0], then axon[i] and dend[j] in run order; ids soma 0, axon 1 + i, dend after.
  std::size_t axons = 0;
  for (std::size_t r = 1; r < runs.size(); ++r) axons += type(runs[r].first) == kAxonType;
  out.length.assign(runs.size(), 0.0);
  std::size_t next_axon = 1, next_dend = 1 + axons;
  for (std::size_t r = 1; r < runs.size(); ++r) {
    const Run& run = runs[r];
    const std::uint32_t id =
        static_cast<std::uint32_t>(type(run.first) == kAxonType ? next_axon++ : next_dend++);
    // The section's first 3-D point: its first point's parent; on the one-point soma, its
    // own first point (a wire to the soma's centre), unless it has only that one point.
    const std::size_t up = parent(run.first);
    const bool own_start = up == 0 && run.end > run.first;
    double arc = 0.0;
    for (std::size_t i = run.first; i <= run.end; ++i) {
      const std::size_t before = i == run.first ? up : i - 1;
      if (!(i == run.first && own_start)) {
        arc += core::norm(point(i) - point(before));
        out.previous[i - 1] = static_cast<std::uint32_t>(before);
      }
      out.arc[i - 1] = arc;
      out.section_of[i - 1] = id;
    }
    out.length[id] = arc;
  }
  return out;
}

SectionPoint locate(const Sections& s, const std::vector<ArbourSample>& samples, std::uint32_t sample, double t) {
  if (sample == 1) return {};
  const std::size_t k = sample - 2;
  // The polyline's piece that ends at the sample (none when the section starts there; a
  // segment ends at a stem's first sample never, so the soma's centre is never `before`).
  const std::uint32_t before = s.previous[k];
  const double seg = before == kNoPoint || before == 0 ? 0.0 : core::norm(samples[k].pos - samples[before - 1].pos);
  const double arc = s.arc[k] - (1.0 - t) * seg;
  const double len = s.length[s.section_of[k]];
  return {s.section_of[k], len > 0.0 ? std::clamp(arc / len, 0.0, 1.0) : 0.0};
}

}  // namespace axg::morphology
