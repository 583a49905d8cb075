#pragma once
// Arbours (SPEC §3.8; docs/methods.md §2.12): the scene section `arbours`, its reading,
// canonical form and checks, and the parameters the arbour engine gives core/branching.hpp
// and core/arbour.hpp. Separate parameters for the axon and the dendrites, under the
// published names of the BESTL model (van Pelt & Uylings 2002): B (B_inf), E, S, tau;
// elongation v0 and F (competition, v0 n^-F), the rate's coefficient of variation between
// cones, the angle between daughters, the persistence length of the heading's walk, the
// diameter (with its taper per centrifugal order), how many stems start at birth (a
// distribution) and at what rate more start afterwards, and the rate of lateral
// (interstitial) branches per length of neurite.
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/arbour.hpp"
#include "axonguide/core/branching.hpp"
#include "axonguide/core/hd.hpp"
#include "axonguide/morphology/arbour_rules.hpp"
#include "axonguide/scene/reader.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct NeuriteKeys {
  // Branching (core/branching.hpp).
  double b = 0.0;                 // B_inf: expected branching events of an isolated segment
  double e = 0.0;                 // E >= 0: competition between the tree's cones
  double s = 0.0;                 // S: the order dependence
  std::optional<double> tau;      // time units, > 0; nullopt: infinite (a constant rate)
  std::optional<double> period;   // with an infinite tau: the time over which B is expected; nullopt: steps x dt
  // Elongation.
  double v0 = 1.0;                // length units per time unit, for a tree of one cone
  double f = 0.0;                 // F >= 0
  double rate_cv = 0.0;           // coefficient of variation of a cone's rate factor (log-normal)
  // Geometry.
  double angle = 1.0;             // radians between two daughters: mean, in (0, pi)
  double angle_sd = 0.0;          // radians
  std::optional<double> persistence_length;  // length units; nullopt: straight between branchings
  double diameter = 1.0;          // micrometres, at a stem
  double taper = 1.0;             // diameter factor per centrifugal order, in (0, 1]
  // Stems: P(k stems at birth) for k = 0, 1, ..., and new stems per neuron per time unit.
  std::vector<double> stems{0.0, 1.0};
  double stem_rate = 0.0;
  // Lateral (interstitial) branching: new cones start along the neurite's existing path at
  // this rate per length unit per time unit (0: off), each at a point the path already has.
  double lateral_rate = 0.0;
};

// The key table of a neurite section (arbours.axon, arbours.dendrites): each key's name, its
// member (a number, or a number that may be null; neither: the stem distribution, read by
// its own rule), its range, its unit, and whether `fit` may fit it. The scene's reader and
// writer and `fit` (study/morphometry_fit.cpp) all take the keys from here.
struct NeuriteKey {
  const char* name;
  double NeuriteKeys::*number;
  std::optional<double> NeuriteKeys::*optional;
  Range range;
  const char* unit;
  bool fittable;
};
const std::vector<NeuriteKey>& neurite_key_table();

struct ArbourKeys {
  double sample_length = 0.0;    // length units: a cone makes a point each time its path grows this much (0: every step)
  double slab = 0.0;             // a culture's growth layer: each stem's height uniform in [0, slab] above the plane
  bool stop_at_soma = true;      // a cone that touches another neuron's soma stops ("stop") or passes ("pass")
  NeuriteKeys axon, dendrites;
  ArbourKeys();
};

// Reads `arbours` (an object; null: no arbours) and checks it: exit 2 for a negative rate,
// E < 0, tau <= 0, a stem-count distribution that is not one, an angle outside (0, pi).
void read_arbour_keys(const nlohmann::json& j, std::optional<ArbourKeys>& out);
nlohmann::json write_arbour_keys(const ArbourKeys& keys);
// Checks against the rest of the scene (the region, the guidance, the steps).
void check_arbours(const Scene& s);

// The rules plus what only the host reads: the stem counts at birth and the diameters.
struct NeuriteParams : ConeRules {
  std::vector<double> stems_cdf;  // cumulative P(k stems at birth)
  double diameter = 1.0, taper = 1.0;
};

struct ArbourParams : ArbourSettings {
  NeuriteParams axon, dendrites;
  ArbourRules rules() const { return {{*this}, axon, dendrites}; }
};

ArbourParams arbour_params(const Scene& s);

// Draws k from a cumulative distribution with one uniform in (0, 1): the first k with
// u < cdf[k] (the last index when rounding leaves u above every entry).
int draw_count(const std::vector<double>& cdf, double u);

}  // namespace axg
