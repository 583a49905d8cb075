#pragma once
// One neuron's arbour as the arbour engine grows it (SPEC §3.8; docs/methods.md §2.12):
// its growth cones, numbered by the tree (never by the thread schedule), its trees (each
// stem and all its descendants), and every point growth made, in the order it made them,
// with the cone that made it and the step that made it: 32 bytes a point. A cone's points,
// in order, are its path, so parents follow from the cones (arbour_samples()). A cone makes
// a point when its path since its last point reaches the sample length, and when it
// branches, stops or the run ends (arbours.sample_length; 0: every step).
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/vec3.hpp"

namespace axg::morphology {

inline constexpr std::uint32_t kNoCone = 0xffffffffu;
inline constexpr std::uint32_t kNoPoint = 0xffffffffu;
inline constexpr std::uint8_t kAxonType = 2, kDendriteType = 3;  // SWC types

enum class ConeStatus : std::uint8_t {
  kGrowing = 0,
  kBranched = 1,  // its segment ended at a branch point (two daughters continue)
  kSoma = 2,      // stopped at another neuron's soma
  kExited = 3,    // left the bounds
};

struct Cone {
  core::Vec3 tip{0, 0, 0};      // the last point (a stem's start before it grows)
  core::Vec3 heading{0, 0, 0};  // unit
  double rate = 1.0;            // its elongation-rate factor
  double length = 0.0;          // of its segment
  double unsampled = 0.0;       // its path since its last point
  std::uint32_t parent = kNoCone;
  // A lateral (interstitial) branch: the index in Arbour::point of the parent's point it
  // starts from; kNoPoint for a stem or a daughter of a branching (which starts from its
  // parent's last point).
  std::uint32_t attach = kNoPoint;
  std::uint32_t born = 0;       // the step at whose end it started (0: at the neuron's birth)
  std::uint32_t ended = 0;      // the last step it grew (born until it grows)
  std::uint16_t tree = 0;
  std::uint8_t type = kAxonType;
  std::uint8_t order = 0;       // centrifugal order (255 at most)
  ConeStatus status = ConeStatus::kGrowing;
  // Cue steering over decision intervals: whether the cone holds the open interval's sums
  // (Arbour::sums) from its start. A stem born inside an interval steers from the next one;
  // a daughter inherits its parent's sums and this flag.
  bool evidence = false;
};

struct Tree {
  std::uint8_t type = kAxonType;
  std::uint32_t born = 0;       // step
  int growing = 0;              // its cones still growing (n of the BESTL model)
  std::vector<int> by_order;    // its growing cones per centrifugal order
  // At the start of the step being taken (morphology/arbour_step.hpp; not stored): its
  // growing cones n, C = the mean of 2^(-S order) over them, the elongation v0 n^-F dt,
  // the branching exponent's tree part and the branching probability at S = 0.
  int n = 0;
  double mean_weight = 1.0, grow = 0.0, branching = 0.0, probability = 0.0;
};

struct Arbour {
  std::vector<core::Vec3> point;       // every point, in the order growth made them
  std::vector<std::uint32_t> cone_of;  // the cone that made each point
  std::vector<std::uint32_t> step_of;  // the step that made each point (a stem's start: its birth step)
  std::vector<Cone> cones;             // by index
  std::vector<std::uint32_t> last;     // each cone's last point (kNoPoint before it makes one)
  std::vector<Tree> trees;             // by index
  std::vector<std::uint32_t> growing;  // the growing cones: those still growing from the last step, then the new ones
  // Cue steering over decision intervals: the open interval's sums of each cone, by cone
  // index, core::kSumsPerCue per cue (empty without them); a stopped cone's are left as they were.
  std::vector<double> sums;

  std::size_t bytes() const {
    return point.capacity() * sizeof(core::Vec3) + cone_of.capacity() * 4 + step_of.capacity() * 4 +
           cones.capacity() * sizeof(Cone) + last.capacity() * 4 +
           trees.capacity() * sizeof(Tree) + growing.capacity() * 4 + sums.capacity() * sizeof(double);
  }
};

// Rebuilds Arbour::last from the points' cones (a checkpoint does not store it).
void link_cones(Arbour& a);

// The arbour as SWC samples (ids from 2; the soma is sample 1): the cones in index order,
// each cone's points in order. A stem's first point's parent is the soma; a daughter's
// first point's parent is its parent cone's last point (the branch point).
struct ArbourSample {
  core::Vec3 pos;
  std::uint32_t parent;  // sample id (1: the soma)
  std::uint32_t cone;
  std::uint32_t step;    // the step that made it (a stem's start: the step it was born)
  std::uint8_t type;
  std::uint8_t order;
};
std::vector<ArbourSample> arbour_samples(const Arbour& a);
// The same order without copying points: each sample's index in Arbour::point and its
// parent sample id (1: the soma), by sample id - 2.
void sample_order(const Arbour& a, std::vector<std::uint32_t>& point_of, std::vector<std::uint32_t>& parent);

// The point each point hangs on, by index in Arbour::point (every one made earlier): its
// cone's previous point; for a cone's first point, its branch point (a lateral branch's
// attach point, or a daughter's parent's last point); kNoPoint for a stem's first point.
void point_parents(const Arbour& a, std::vector<std::uint32_t>& out);


// Summary numbers of one arbour (neurons.csv for arbour scenes).
struct ArbourSummary {
  double axon_length = 0;             // the axon's segments (stem starts excluded)
  core::Vec3 farthest{0, 0, 0};       // the axon point farthest from the soma (lowest sample on ties)
  std::uint32_t last_step = 0;        // the last step any cone grew
  bool growing = false;
};
ArbourSummary summarize(const Arbour& a, core::Vec3 soma);

// Checkpoints: every arbour, in neuron order, as bytes (and back; throws std::runtime_error
// on a malformed blob).
void append_arbours(const std::vector<Arbour>& arbours, std::vector<std::uint8_t>& out);
std::vector<Arbour> read_arbours(const std::vector<std::uint8_t>& in);

}  // namespace axg::morphology
