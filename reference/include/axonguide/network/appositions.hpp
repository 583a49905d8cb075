#pragma once
// Appositions where axons pass dendrites (SPEC §3.9; docs/methods.md §2.13), on the final
// arbours.
//
// A segment is an SWC sample with its parent, except a stem's first sample (its segment
// from the soma's centre lies inside the soma): segment s runs from sample parent(s) to
// sample s, and is named by s, its distal sample. A contact is (a segment of neuron i's
// axon, a segment of a dendrite of neuron j or j's soma), j != i unless autapses are asked
// for, whose centrelines come within d (to a soma: the distance to its centre minus its
// radius; a neuron's own soma, which its axon starts on, never counts). Two contacts of one pair are neighbours when their axon segments are the same
// or parent and child, and their dendrite segments too (the soma is one segment, the parent
// of each dendrite's first segment). Each connected group of contacts is one apposition,
// placed at its closest contact (ties: the lowest axon sample, then the lowest dendrite
// sample). Its step is the first step at which one of its contacts existed (a contact's
// step is the later of its two segments' steps; a soma's is 0).
//
// Detection sorts the dendrite segments and somas into a spatial hash (hash, stable sort,
// cell ranges), each in every cell its box grown by d covers, and visits each pair once:
// in the cell of the lowest corner of the two boxes' overlap. Brute force (every pair) is
// the oracle; both give the same contacts, which are then sorted by (pre, post, axon
// sample, dendrite sample), so nothing depends on the thread count.
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/model/synapses.hpp"
#include "axonguide/morphology/arbour.hpp"

namespace axg::network {

inline constexpr std::uint32_t kSomaSample = 1;
inline constexpr std::uint32_t kNoSegment = 0;  // a root segment's parent on the axon side

// Every neuron's segments, neuron by neuron, by sample id: a view over the arbours' own
// points and steps (9 bytes a sample: its point, its proximal sample, its type), so that
// detection does not copy the arbours. Accessors take the sample's neuron and its global
// index k (neuron n's sample s is k = first[n] + s - 2). Move-only: the view points into
// the arbours (or, built from polylines, into its own storage).
struct Segments {
  std::vector<std::uint64_t> first;             // neurons + 1
  std::vector<const core::Vec3*> points;        // by neuron: its points
  std::vector<const std::uint32_t*> steps;      // by neuron: the step that made each point
  std::vector<std::uint32_t> point;             // by sample: its index in its neuron's points
  std::vector<std::uint32_t> up;                // by sample: its parent sample id (kSomaSample: a stem start)
  std::vector<std::uint8_t> type;               // by sample: SWC type
  std::vector<core::Vec3> soma;
  double soma_radius = 0.0;
  std::vector<core::Vec3> own_points;           // segments_from_polylines' storage
  std::vector<std::uint32_t> own_steps;

  Segments() = default;
  Segments(Segments&&) = default;
  Segments& operator=(Segments&&) = default;
  Segments(const Segments&) = delete;
  Segments& operator=(const Segments&) = delete;

  std::size_t neurons() const { return soma.size(); }
  std::size_t size() const { return point.size(); }
  core::Vec3 p1(std::uint32_t n, std::uint64_t k) const { return points[n][point[k]]; }
  // The proximal point (a stem start, which is no segment: its own).
  core::Vec3 p0(std::uint32_t n, std::uint64_t k) const {
    return up[k] == kSomaSample ? p1(n, k) : p1(n, first[n] + up[k] - 2);
  }
  std::uint32_t step(std::uint32_t n, std::uint64_t k) const { return steps[n][point[k]]; }
  bool is_segment(std::uint64_t k) const { return up[k] != kSomaSample; }
  // The parent segment of neuron n's sample: its parent sample, the soma (kSomaSample) when
  // that is a stem start, kNoSegment for a stem start or the soma itself.
  std::uint32_t parent_of(std::uint32_t n, std::uint32_t sample) const {
    if (sample == kSomaSample) return kNoSegment;
    const std::uint32_t u = up[first[n] + sample - 2];
    if (u == kSomaSample) return kNoSegment;
    return up[first[n] + u - 2] == kSomaSample ? kSomaSample : u;
  }
};

Segments segments_of(const std::vector<morphology::Arbour>& arbours, const std::vector<core::Vec3>& soma,
                     double soma_radius);

// Neurites given as polylines (tests and validation): each starts at a stem start (a sample
// whose parent is the soma) or at the first point after a branch from an earlier sample of
// the same neuron; its k-th point was made at step + k.
struct Polyline {
  std::uint8_t type = morphology::kAxonType;
  std::vector<core::Vec3> points;
  std::uint32_t from = kSomaSample;  // the sample it hangs on (kSomaSample: a new stem)
  std::uint32_t step = 0;
};
Segments segments_from_polylines(const std::vector<std::vector<Polyline>>& neurons, const std::vector<core::Vec3>& soma,
                                 double soma_radius);

struct Contact {
  std::uint32_t pre = 0, post = 0;
  std::uint32_t pre_sample = 0, post_sample = 0;  // the two segments' distal samples (a soma: 1)
  std::uint32_t step = 0;
  double distance = 0.0;    // length units (to a soma: minus its radius)
  double s = 0.0, t = 0.0;  // the closest points' parameters along the axon and the dendrite segment (a soma: t = 0)
  bool operator==(const Contact&) const = default;  // every field exactly
};

// The closest points of a contact: on the axon segment, and on the dendrite segment (a
// soma: on its surface toward the axon's point; its centre when that point is the centre).
core::Vec3 axon_point(const Segments& g, const Contact& c);
core::Vec3 dendrite_point(const Segments& g, const Contact& c);

// The contacts, sorted by (pre, post, pre_sample, post_sample). cells_visited, when not
// null, receives the (cell, axon segment) visits the hash made (a cost statistic).
std::vector<Contact> find_contacts(const Segments& g, double d, bool autapses, std::uint64_t* cells_visited = nullptr);
// The oracle: every (axon segment, dendrite segment or soma) pair, the same order.
std::vector<Contact> find_contacts_brute(const Segments& g, double d, bool autapses);

struct Appositions {
  // One entry per apposition, sorted by (pre, post, pre_sample, post_sample).
  std::vector<Contact> at;             // its closest contact (step: the apposition's first step)
  std::vector<core::Vec3> on_axon, on_dendrite;  // that contact's closest points
  std::vector<std::uint32_t> contacts;  // the run's size
  std::vector<std::uint8_t> realised;
  std::size_t size() const { return at.size(); }
};

// Groups sorted contacts into appositions and realises them: each with probability p by a
// draw on (seed, kSynapse, pre, post, pre_sample, post_sample), then, per connection, the
// first `cap` realised ones in (pre_sample, post_sample) order.
Appositions group_appositions(const Segments& g, const std::vector<Contact>& contacts, const SynapseParams& p);

// The same appositions straight from the segments, a chunk of whole neurons at a time, so
// that the contacts are never all held at once (the run's path); contacts, when not null,
// receives how many there were.
Appositions find_appositions(const Segments& g, const SynapseParams& p, std::uint64_t* contacts = nullptr);

// A connection i -> j with at least one realised synapse.
struct Connection {
  std::uint32_t source, target, synapses, first_step;
};
std::vector<Connection> connections_of(const Appositions& a);

}  // namespace axg::network
