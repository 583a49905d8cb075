// Appositions where axons pass dendrites (SPEC §3.9; docs/methods.md §2.13).
#include "axonguide/network/appositions.hpp"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/random.hpp"
#include "axonguide/core/segment.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/radix_sort.hpp"

namespace axg::network {

using core::Vec3;

Segments segments_of(const std::vector<morphology::Arbour>& arbours, const std::vector<Vec3>& soma,
                     double soma_radius) {
  Segments g;
  const std::size_t n = arbours.size();
  g.soma = soma;
  g.soma_radius = soma_radius;
  g.first.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) g.first[i + 1] = g.first[i] + arbours[i].point.size();
  const std::size_t total = g.first[n];
  g.points.resize(n);
  g.steps.resize(n);
  g.point.resize(total);
  g.up.resize(total);
  g.type.resize(total);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const morphology::Arbour& a = arbours[i];
    g.points[i] = a.point.data();
    g.steps[i] = a.step_of.data();
    std::vector<std::uint32_t> point_of, parent;
    morphology::sample_order(a, point_of, parent);
    const std::uint64_t base = g.first[i];
    for (std::size_t k = 0; k < point_of.size(); ++k) {
      g.point[base + k] = point_of[k];
      g.up[base + k] = parent[k];
      g.type[base + k] = a.cones[a.cone_of[point_of[k]]].type;
    }
  });
  return g;
}

Segments segments_from_polylines(const std::vector<std::vector<Polyline>>& neurons, const std::vector<Vec3>& soma,
                                 double soma_radius) {
  Segments g;
  g.soma = soma;
  g.soma_radius = soma_radius;
  g.first.push_back(0);
  for (const auto& lines : neurons) {
    const std::uint64_t base = g.first.back();
    std::uint32_t next = 2;
    for (const Polyline& l : lines) {
      std::uint32_t up = l.from;
      for (std::size_t k = 0; k < l.points.size(); ++k) {
        g.point.push_back(static_cast<std::uint32_t>(g.own_points.size() - base));  // index in its neuron's points
        g.up.push_back(up);
        g.own_points.push_back(l.points[k]);
        g.own_steps.push_back(l.step + static_cast<std::uint32_t>(k));
        g.type.push_back(l.type);
        up = next++;
      }
    }
    g.first.push_back(base + (next - 2));
  }
  // Each neuron's points start at its first sample in the own storage (complete now).
  for (std::size_t n = 0; n + 1 < g.first.size(); ++n) {
    g.points.push_back(g.own_points.data() + g.first[n]);
    g.steps.push_back(g.own_steps.data() + g.first[n]);
  }
  return g;
}

namespace {

// An axon segment against a dendrite segment (or a soma: dendrite_sample 1): the contact
// when they come within d.
bool try_contact(const Segments& g, std::uint32_t pre, std::uint64_t a, std::uint32_t post, std::uint64_t dk,
                 bool soma, double d, Contact& out) {
  const Vec3 p0 = g.p0(pre, a), p1 = g.p1(pre, a);
  if (soma) {
    const Vec3 c = g.soma[post];
    const double s = core::closest_parameter(p0, p1, c);
    const Vec3 on = p0 + s * (p1 - p0);
    const double centre = core::norm(on - c);
    const double dist = centre - g.soma_radius;
    if (!(dist <= d)) return false;
    out.distance = dist;
    out.s = s;
    out.t = 0.0;
    out.post_sample = kSomaSample;
    out.step = g.step(pre, a);
  } else {
    const Vec3 q0 = g.p0(post, dk), q1 = g.p1(post, dk);
    const core::SegmentPair cp = core::closest_points(p0, p1, q0, q1);
    if (!(cp.dist2 <= d * d)) return false;
    out.distance = std::sqrt(cp.dist2);
    out.s = cp.s;
    out.t = cp.t;
    out.post_sample = static_cast<std::uint32_t>(dk - g.first[post] + 2);
    out.step = std::max(g.step(pre, a), g.step(post, dk));
  }
  out.pre = pre;
  out.post = post;
  out.pre_sample = static_cast<std::uint32_t>(a - g.first[pre] + 2);
  return true;
}

}  // namespace

Vec3 axon_point(const Segments& g, const Contact& c) {
  const std::uint64_t a = g.first[c.pre] + c.pre_sample - 2;
  const Vec3 p0 = g.p0(c.pre, a);
  return p0 + c.s * (g.p1(c.pre, a) - p0);
}

Vec3 dendrite_point(const Segments& g, const Contact& c) {
  if (c.post_sample == kSomaSample) {
    const Vec3 centre = g.soma[c.post], on = axon_point(g, c);
    const double r = core::norm(on - centre);
    return r > 0.0 ? centre + (g.soma_radius / r) * (on - centre) : centre;
  }
  const std::uint64_t k = g.first[c.post] + c.post_sample - 2;
  const Vec3 q0 = g.p0(c.post, k);
  return q0 + c.t * (g.p1(c.post, k) - q0);
}

namespace {

bool contact_less(const Contact& x, const Contact& y) {
  if (x.pre != y.pre) return x.pre < y.pre;
  if (x.post != y.post) return x.post < y.post;
  if (x.pre_sample != y.pre_sample) return x.pre_sample < y.pre_sample;
  return x.post_sample < y.post_sample;
}

// The dendrite side: every dendrite segment (by global sample index) and its neuron; and
// each neuron's axon segment count (the query walks neurons, not a list of axon segments).
struct Sides {
  std::vector<std::uint64_t> dendrite;
  std::vector<std::uint32_t> owner_dendrite;
  std::vector<std::uint64_t> axons;  // by neuron
  std::uint64_t axon_total = 0;
};

Sides sides_of(const Segments& g) {
  Sides s;
  s.axons.assign(g.neurons(), 0);
  for (std::size_t n = 0; n < g.neurons(); ++n)
    for (std::uint64_t k = g.first[n]; k < g.first[n + 1]; ++k) {
      if (!g.is_segment(k)) continue;
      if (g.type[k] == morphology::kAxonType) {
        ++s.axons[n];
      } else {
        s.dendrite.push_back(k);
        s.owner_dendrite.push_back(static_cast<std::uint32_t>(n));
      }
    }
  s.axon_total = std::accumulate(s.axons.begin(), s.axons.end(), std::uint64_t{0});
  return s;
}

// Calls f(neuron, k) for every axon segment of the neurons [n0, n1), in order.
template <class F>
void for_axon_segments(const Segments& g, std::size_t n0, std::size_t n1, F&& f) {
  for (std::size_t n = n0; n < n1; ++n)
    for (std::uint64_t k = g.first[n]; k < g.first[n + 1]; ++k)
      if (g.is_segment(k) && g.type[k] == morphology::kAxonType) f(static_cast<std::uint32_t>(n), k);
}

struct Box {
  Vec3 lo, hi;
};
Box box_of(Vec3 a, Vec3 b, double grow) {
  return {{std::min(a.x, b.x) - grow, std::min(a.y, b.y) - grow, std::min(a.z, b.z) - grow},
          {std::max(a.x, b.x) + grow, std::max(a.y, b.y) + grow, std::max(a.z, b.z) + grow}};
}

struct Cell {
  std::int64_t x, y, z;
  bool operator==(const Cell&) const = default;
};

class Hash {
 public:
  Hash(Vec3 origin, double cell, std::uint32_t bits) : origin_(origin), cell_(cell), mask_((1u << bits) - 1u) {}
  Cell cell_of(Vec3 p) const {
    return {static_cast<std::int64_t>((p.x - origin_.x) / cell_), static_cast<std::int64_t>((p.y - origin_.y) / cell_),
            static_cast<std::int64_t>((p.z - origin_.z) / cell_)};
  }
  std::uint32_t key(Cell c) const {
    // Neighbours along x in neighbouring slots (an axon's cells, visited in a row, share
    // cache lines); rows along y and z spread by odd multipliers.
    const std::uint64_t h = static_cast<std::uint64_t>(c.x) + static_cast<std::uint64_t>(c.y) * 0x9E3779B1ull +
                            static_cast<std::uint64_t>(c.z) * 0x85EBCA77C2B2AE63ull;
    return static_cast<std::uint32_t>(h ^ (h >> 32)) & mask_;
  }
  std::uint32_t max_key() const { return mask_; }

 private:
  Vec3 origin_;
  double cell_;
  std::uint32_t mask_;
};

template <class F>
void for_cells(Cell lo, Cell hi, F f) {
  for (std::int64_t z = lo.z; z <= hi.z; ++z)
    for (std::int64_t y = lo.y; y <= hi.y; ++y)
      for (std::int64_t x = lo.x; x <= hi.x; ++x) f(Cell{x, y, z});
}

// Axon segments per chunk of the query (at least; chunks hold whole neurons).
constexpr std::size_t kAxonChunk = 4096;

}  // namespace

namespace {

// The hash's query in chunks of whole neurons: init(chunks) once, then, in parallel,
// sink(chunk, contacts) with each chunk's contacts sorted by (pre, post, pre_sample,
// post_sample); chunks in order make the sorted whole. Returns the (cell, axon segment)
// visits.
template <class Init, class Sink>
std::uint64_t query_chunks(const Segments& g, double d, bool autapses, Init&& init, Sink&& sink) {
  const Sides sd = sides_of(g);
  // The dendrite side: its segments, then the somas (item index dendrite.size() + neuron).
  const std::size_t nd = sd.dendrite.size(), items = nd + g.neurons();
  auto item_box = [&](std::size_t k) {
    if (k < nd) return box_of(g.p0(sd.owner_dendrite[k], sd.dendrite[k]), g.p1(sd.owner_dendrite[k], sd.dendrite[k]), d);
    const Vec3 c = g.soma[k - nd];
    return box_of(c, c, d + g.soma_radius);
  };
  if (items == 0 || sd.axon_total == 0) {
    init(std::size_t{0});
    return 0;
  }
  // The cell: at least 2d and twice the mean axon and dendrite segment length, so that a
  // segment's box covers a few cells (in a culture at the bench's density, twice the mean
  // length took 0.98 s of queries against 1.22 s at once the mean, with a quarter of the
  // entries; `axonguide bench synapses`); its origin the lowest corner of every box.
  Vec3 origin{HUGE_VAL, HUGE_VAL, HUGE_VAL};
  Vec3 top{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  double length = 0.0;
  auto extend = [&](const Box& b) {
    origin = {std::min(origin.x, b.lo.x), std::min(origin.y, b.lo.y), std::min(origin.z, b.lo.z)};
    top = {std::max(top.x, b.hi.x), std::max(top.y, b.hi.y), std::max(top.z, b.hi.z)};
  };
  for (std::size_t k = 0; k < items; ++k) extend(item_box(k));
  for_axon_segments(g, 0, g.neurons(), [&](std::uint32_t n, std::uint64_t a) {
    extend(box_of(g.p0(n, a), g.p1(n, a), 0.0));
    length += core::norm(g.p1(n, a) - g.p0(n, a));
  });
  for (std::size_t k = 0; k < nd; ++k)
    length += core::norm(g.p1(sd.owner_dendrite[k], sd.dendrite[k]) - g.p0(sd.owner_dendrite[k], sd.dendrite[k]));
  const double extent = std::max({top.x - origin.x, top.y - origin.y, top.z - origin.z});
  const double cell =
      std::max({2.0 * d, 2.0 * length / static_cast<double>(sd.axon_total + nd), extent / 1048576.0});
  // Entries: every item in every cell its grown box covers, counted then filled, items in
  // order; then a stable sort by slot.
  const Hash sizing(origin, cell, 1);
  std::vector<std::uint64_t> count(items + 1, 0);
  tbb::parallel_for(std::size_t{0}, items, [&](std::size_t k) {
    const Box b = item_box(k);
    const Cell lo = sizing.cell_of(b.lo), hi = sizing.cell_of(b.hi);
    count[k + 1] = static_cast<std::uint64_t>(hi.x - lo.x + 1) * static_cast<std::uint64_t>(hi.y - lo.y + 1) *
                   static_cast<std::uint64_t>(hi.z - lo.z + 1);
  });
  std::partial_sum(count.begin(), count.end(), count.begin());
  // Table slots: a power of two of at least the entry count, so that a slot holds about
  // one cell's items (at the item count instead, detection took 2.6 times as long).
  std::uint32_t bits = 10;
  while (bits < 31 && (std::uint64_t{1} << bits) < count[items]) ++bits;
  const Hash hash(origin, cell, bits);
  if (count[items] >= 0xffffffffull)
    throw RunError(fmt::format("synapses: {} hash entries (dendrite segments times the cells each covers): more "
                               "than 32-bit entry ids hold; lower synapses.distance or the neuron count",
                               count[items]));
  std::vector<std::uint32_t> keys(count[items]), values(count[items]);
  tbb::parallel_for(std::size_t{0}, items, [&](std::size_t k) {
    const Box b = item_box(k);
    std::uint64_t e = count[k];
    for_cells(hash.cell_of(b.lo), hash.cell_of(b.hi), [&](Cell c) {
      keys[e] = hash.key(c);
      values[e] = static_cast<std::uint32_t>(k);
      ++e;
    });
  });
  stable_sort_by_key(keys, values, hash.max_key());
  std::vector<std::uint32_t> start;
  cell_starts(keys, hash.max_key() + 1u, start);
  keys = {};

  // Queries: each axon segment visits the cells of its box; a pair counts only in the cell
  // of the lowest corner of its two boxes' overlap, so once.
  // Chunks of whole neurons (at least kAxonChunk axon segments each, but the last): each
  // sorts its own contacts, and their concatenation is the sorted whole.
  std::vector<std::size_t> bounds{0};  // neuron ranges
  std::uint64_t in_chunk = 0;
  for (std::size_t n = 0; n < g.neurons(); ++n) {
    in_chunk += sd.axons[n];
    if (in_chunk >= kAxonChunk && n + 1 < g.neurons()) {
      bounds.push_back(n + 1);
      in_chunk = 0;
    }
  }
  bounds.push_back(g.neurons());
  const std::size_t chunks = bounds.size() - 1;
  init(chunks);
  std::vector<std::uint64_t> visits(chunks, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t ch) {
    std::vector<Contact> found;
    for_axon_segments(g, bounds[ch], bounds[ch + 1], [&](std::uint32_t pre, std::uint64_t a) {
      const Box ab = box_of(g.p0(pre, a), g.p1(pre, a), 0.0);
      for_cells(hash.cell_of(ab.lo), hash.cell_of(ab.hi), [&](Cell c) {
        ++visits[ch];
        const std::uint32_t slot = hash.key(c);
        for (std::uint32_t e = start[slot]; e < start[slot + 1]; ++e) {
          const std::uint32_t k = values[e];
          // An item in two cells of one slot has two adjacent entries there: one visit.
          if (e > start[slot] && values[e - 1] == k) continue;
          const Box db = item_box(k);
          const Box both{{std::max(ab.lo.x, db.lo.x), std::max(ab.lo.y, db.lo.y), std::max(ab.lo.z, db.lo.z)},
                         {std::min(ab.hi.x, db.hi.x), std::min(ab.hi.y, db.hi.y), std::min(ab.hi.z, db.hi.z)}};
          if (both.lo.x > both.hi.x || both.lo.y > both.hi.y || both.lo.z > both.hi.z) continue;
          if (!(hash.cell_of(both.lo) == c)) continue;  // another cell (or another cell's slot) counts it
          const bool soma = k >= nd;
          const std::uint32_t post = soma ? static_cast<std::uint32_t>(k - nd) : sd.owner_dendrite[k];
          if (post == pre && (!autapses || soma)) continue;
          Contact ct;
          if (try_contact(g, pre, a, post, soma ? 0 : sd.dendrite[k], soma, d, ct)) found.push_back(ct);
        }
      });
    });
    std::sort(found.begin(), found.end(), contact_less);
    sink(ch, found);
  });
  return std::accumulate(visits.begin(), visits.end(), std::uint64_t{0});
}

}  // namespace

std::vector<Contact> find_contacts(const Segments& g, double d, bool autapses, std::uint64_t* cells_visited) {
  std::vector<std::vector<Contact>> found;
  const std::uint64_t visits = query_chunks(
      g, d, autapses, [&](std::size_t chunks) { found.resize(chunks); },
      [&](std::size_t ch, std::vector<Contact>& contacts) { found[ch] = std::move(contacts); });
  std::vector<Contact> out;
  std::size_t total = 0;
  for (const auto& f : found) total += f.size();
  out.reserve(total);
  for (auto& f : found) {
    out.insert(out.end(), f.begin(), f.end());
    f = {};
  }
  if (cells_visited) *cells_visited = visits;
  return out;
}

std::vector<Contact> find_contacts_brute(const Segments& g, double d, bool autapses) {
  const Sides sd = sides_of(g);
  std::vector<Contact> out;
  for_axon_segments(g, 0, g.neurons(), [&](std::uint32_t pre, std::uint64_t a) {
    for (std::size_t k = 0; k < sd.dendrite.size() + g.neurons(); ++k) {
      const bool soma = k >= sd.dendrite.size();
      const std::uint32_t post = soma ? static_cast<std::uint32_t>(k - sd.dendrite.size()) : sd.owner_dendrite[k];
      if (post == pre && (!autapses || soma)) continue;
      Contact ct;
      if (try_contact(g, pre, a, post, soma ? 0 : sd.dendrite[k], soma, d, ct)) out.push_back(ct);
    }
  });
  std::sort(out.begin(), out.end(), contact_less);
  return out;
}

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& up, std::uint32_t x) {
  while (up[x] != x) {
    up[x] = up[up[x]];
    x = up[x];
  }
  return x;
}

// Whether two segments of one neuron are the same, or parent and child.
bool adjacent(const Segments& g, std::uint32_t neuron, std::uint32_t x, std::uint32_t y) {
  return x == y || g.parent_of(neuron, x) == y || g.parent_of(neuron, y) == x;
}

}  // namespace

namespace {

// The runs of sorted contacts (whole neuron pairs), sorted by their closest contacts; not
// yet realised.
Appositions runs_of(const Segments& g, const std::vector<Contact>& contacts) {
  Appositions out;
  const std::size_t n = contacts.size();
  if (n == 0) return out;
  std::vector<std::uint32_t> up(n);
  std::iota(up.begin(), up.end(), 0u);
  // One neuron pair at a time (contacts sorted by pair, then axon sample, then dendrite
  // sample): a contact meets the pair's contacts on its own axon segment and on its axon
  // segment's parent; union by the lowest index keeps every root the run's first contact.
  std::vector<std::size_t> groups{0};  // where each neuron pair's contacts start
  for (std::size_t c = 1; c < n; ++c)
    if (contacts[c].pre != contacts[c - 1].pre || contacts[c].post != contacts[c - 1].post) groups.push_back(c);
  groups.push_back(n);
  // Pairs are independent (each touches only its own contacts' entries of `up`).
  tbb::parallel_for(std::size_t{0}, groups.size() - 1, [&](std::size_t q) {
    const std::size_t g0 = groups[q], g1 = groups[q + 1];
    const std::uint32_t pre = contacts[g0].pre, post = contacts[g0].post;
    auto by_axon = [&](std::uint32_t sample) {
      auto lo = std::partition_point(contacts.begin() + g0, contacts.begin() + g1,
                                     [&](const Contact& c) { return c.pre_sample < sample; });
      auto hi = std::partition_point(lo, contacts.begin() + g1, [&](const Contact& c) { return c.pre_sample == sample; });
      return std::pair{static_cast<std::size_t>(lo - contacts.begin()), static_cast<std::size_t>(hi - contacts.begin())};
    };
    for (std::size_t c = g0; c < g1; ++c) {
      const std::uint32_t axon_up = g.parent_of(pre, contacts[c].pre_sample);
      for (const std::uint32_t sample : {contacts[c].pre_sample, axon_up}) {
        if (sample == kNoSegment || sample == kSomaSample) continue;
        const auto [lo, hi] = by_axon(sample);
        for (std::size_t o = lo; o < hi; ++o) {
          if (o == c || !adjacent(g, post, contacts[c].post_sample, contacts[o].post_sample)) continue;
          const std::uint32_t rc = find_root(up, static_cast<std::uint32_t>(c)), ro = find_root(up, static_cast<std::uint32_t>(o));
          if (rc != ro) up[std::max(rc, ro)] = std::min(rc, ro);
        }
      }
    }
  });
  // Each run: its closest contact (ties: the lowest axon sample, then dendrite sample, which
  // is the contacts' order), its size, its first step.
  std::vector<std::uint32_t> index(n, 0xffffffffu);
  for (std::size_t c = 0; c < n; ++c) {
    const std::uint32_t r = find_root(up, static_cast<std::uint32_t>(c));
    if (index[r] == 0xffffffffu) {
      index[r] = static_cast<std::uint32_t>(out.at.size());
      out.at.push_back(contacts[c]);
      out.contacts.push_back(0);
    }
    const std::uint32_t k = index[r];
    Contact& best = out.at[k];
    const std::uint32_t first = std::min(best.step, contacts[c].step);
    if (contacts[c].distance < best.distance) best = contacts[c];
    best.step = first;
    ++out.contacts[k];
  }
  // Sorted by their closest contacts.
  std::vector<std::uint32_t> order(out.at.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return contact_less(out.at[x], out.at[y]); });
  Appositions sorted;
  sorted.at.reserve(order.size());
  for (const std::uint32_t k : order) {
    sorted.at.push_back(out.at[k]);
    sorted.contacts.push_back(out.contacts[k]);
    sorted.on_axon.push_back(axon_point(g, out.at[k]));
    sorted.on_dendrite.push_back(dendrite_point(g, out.at[k]));
  }
  return sorted;
}

// Realisation: a draw each, then the cap per connection in (pre_sample, post_sample) order.
void realise(Appositions& sorted, const SynapseParams& p) {
  sorted.realised.assign(sorted.at.size(), 0);
  std::uint32_t kept = 0;
  for (std::size_t k = 0; k < sorted.at.size(); ++k) {
    const Contact& c = sorted.at[k];
    if (k == 0 || c.pre != sorted.at[k - 1].pre || c.post != sorted.at[k - 1].post) kept = 0;
    if (c.post_sample >= (1u << 24))
      throw RunError(fmt::format("synapses: neuron {} has dendrite sample {}: the realisation draw's key holds "
                                 "samples below 2^24 (raise arbours.sample_length)",
                                 c.post, c.post_sample));
    bool real = true;
    if (p.probability < 1.0) {
      core::Rng rng(p.seed, core::Stream::kSynapse, static_cast<std::uint64_t>(c.pre) | (std::uint64_t{c.post_sample} << 32),
                    c.post, c.pre_sample);
      real = rng.uniform() < p.probability;
    }
    if (real && kept < p.cap) {
      sorted.realised[k] = 1;
      ++kept;
    }
  }
}

}  // namespace

Appositions group_appositions(const Segments& g, const std::vector<Contact>& contacts, const SynapseParams& p) {
  Appositions a = runs_of(g, contacts);
  realise(a, p);
  return a;
}

Appositions find_appositions(const Segments& g, const SynapseParams& p, std::uint64_t* contacts) {
  // Each chunk's contacts become its runs at once (a neuron pair never spans two chunks),
  // so the contacts are never all held together.
  std::vector<Appositions> parts;
  std::vector<std::uint64_t> counts;
  query_chunks(
      g, p.distance, p.autapses,
      [&](std::size_t chunks) {
        parts.resize(chunks);
        counts.assign(chunks, 0);
      },
      [&](std::size_t ch, std::vector<Contact>& found) {
        counts[ch] = found.size();
        parts[ch] = runs_of(g, found);
        found = {};
      });
  Appositions out;
  std::size_t total = 0;
  for (const Appositions& a : parts) total += a.size();
  out.at.reserve(total);
  out.contacts.reserve(total);
  out.on_axon.reserve(total);
  out.on_dendrite.reserve(total);
  for (Appositions& a : parts) {
    out.at.insert(out.at.end(), a.at.begin(), a.at.end());
    out.contacts.insert(out.contacts.end(), a.contacts.begin(), a.contacts.end());
    out.on_axon.insert(out.on_axon.end(), a.on_axon.begin(), a.on_axon.end());
    out.on_dendrite.insert(out.on_dendrite.end(), a.on_dendrite.begin(), a.on_dendrite.end());
    a = {};
  }
  realise(out, p);
  if (contacts) *contacts = std::accumulate(counts.begin(), counts.end(), std::uint64_t{0});
  return out;
}

std::vector<Connection> connections_of(const Appositions& a) {
  std::vector<Connection> out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (!a.realised[k]) continue;
    const Contact& c = a.at[k];
    if (out.empty() || out.back().source != c.pre || out.back().target != c.post)
      out.push_back({c.pre, c.post, 0, c.step});
    ++out.back().synapses;
    out.back().first_step = std::min(out.back().first_step, c.step);
  }
  return out;
}

}  // namespace axg::network
