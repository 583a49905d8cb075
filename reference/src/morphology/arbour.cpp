// Arbours as grown, as SWC samples, summarised, and as checkpoint bytes (docs/methods.md §2.12).
#include "axonguide/morphology/arbour.hpp"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace axg::morphology {

void point_parents(const Arbour& a, std::vector<std::uint32_t>& out) {
  std::vector<std::uint32_t> last(a.cones.size(), kNoPoint);  // each cone's last point so far
  out.assign(a.point.size(), kNoPoint);
  for (std::size_t i = 0; i < a.point.size(); ++i) {
    const std::uint32_t c = a.cone_of[i];
    const Cone& cone = a.cones[c];
    std::uint32_t b = last[c];
    // A branched cone made a point when it branched, before its daughters made theirs.
    if (b == kNoPoint && cone.parent != kNoCone) b = cone.attach != kNoPoint ? cone.attach : last[cone.parent];
    out[i] = b;
    last[c] = static_cast<std::uint32_t>(i);
  }
}

void link_cones(Arbour& a) {
  a.last.assign(a.cones.size(), kNoPoint);
  for (std::size_t i = 0; i < a.point.size(); ++i) a.last[a.cone_of[i]] = static_cast<std::uint32_t>(i);
}

void sample_order(const Arbour& a, std::vector<std::uint32_t>& point_of, std::vector<std::uint32_t>& parent) {
  const std::size_t cones = a.cones.size();
  std::vector<std::uint32_t> count(cones, 0), first(cones + 1, 0);
  for (const std::uint32_t c : a.cone_of) ++count[c];
  for (std::size_t c = 0; c < cones; ++c) first[c + 1] = first[c] + count[c];
  std::vector<std::uint32_t> fill(cones, 0), parents, sample_of(a.point.size());
  point_parents(a, parents);
  point_of.assign(a.point.size(), 0);
  parent.assign(a.point.size(), 1u);
  // Samples: the cones in index order, each cone's points in order; a point's parent is
  // the sample of the point it hangs on (made earlier, so numbered already), or the soma.
  for (std::size_t i = 0; i < a.point.size(); ++i) {
    const std::uint32_t c = a.cone_of[i];
    sample_of[i] = 2u + first[c] + fill[c]++;
    point_of[sample_of[i] - 2u] = static_cast<std::uint32_t>(i);
    parent[sample_of[i] - 2u] = parents[i] == kNoPoint ? 1u : sample_of[parents[i]];
  }
}

std::vector<ArbourSample> arbour_samples(const Arbour& a) {
  std::vector<std::uint32_t> point_of, parent;
  sample_order(a, point_of, parent);
  std::vector<ArbourSample> out(a.point.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::uint32_t i = point_of[k];
    const Cone& cone = a.cones[a.cone_of[i]];
    out[k] = {a.point[i], parent[k], a.cone_of[i], a.step_of[i], cone.type, cone.order};
  }
  return out;
}

ArbourSummary summarize(const Arbour& a, core::Vec3 soma) {
  ArbourSummary s;
  for (const Cone& c : a.cones) {
    if (c.type == kAxonType) s.axon_length += c.length;
    if (c.ended > s.last_step) s.last_step = c.ended;
    if (c.status == ConeStatus::kGrowing) s.growing = true;
  }
  double best = -1.0;
  for (std::size_t i = 0; i < a.point.size(); ++i) {
    if (a.cones[a.cone_of[i]].type != kAxonType) continue;
    const double d = core::norm2(a.point[i] - soma);
    if (d > best) {
      best = d;
      s.farthest = a.point[i];
    }
  }
  if (best < 0.0) s.farthest = soma;
  return s;
}

namespace {

template <class T>
void put(std::vector<std::uint8_t>& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

template <class T>
void put_array(std::vector<std::uint8_t>& out, const std::vector<T>& v) {
  put<std::uint64_t>(out, v.size());
  const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
  out.insert(out.end(), p, p + v.size() * sizeof(T));
}

class Cursor {
 public:
  explicit Cursor(const std::vector<std::uint8_t>& in) : in_(in) {}
  template <class T>
  T get() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  void get_array(std::vector<T>& v) {
    const auto n = get<std::uint64_t>();
    if (n > (in_.size() - at_) / sizeof(T)) throw std::runtime_error("checkpoint: an arbour array longer than its bytes");
    v.resize(n);
    take(v.data(), n * sizeof(T));
  }
  bool done() const { return at_ == in_.size(); }

 private:
  void take(void* p, std::size_t n) {
    if (n > in_.size() - at_) throw std::runtime_error("checkpoint: the arbours are truncated");
    std::memcpy(p, in_.data() + at_, n);
    at_ += n;
  }
  const std::vector<std::uint8_t>& in_;
  std::size_t at_ = 0;
};

}  // namespace

void append_arbours(const std::vector<Arbour>& arbours, std::vector<std::uint8_t>& out) {
  put<std::uint64_t>(out, arbours.size());
  for (const Arbour& a : arbours) {
    put_array(out, a.point);
    put_array(out, a.cone_of);
    put_array(out, a.step_of);
    put<std::uint64_t>(out, a.cones.size());
    for (const Cone& c : a.cones) {  // field by field: no padding bytes
      put(out, c.tip);
      put(out, c.heading);
      put(out, c.rate);
      put(out, c.length);
      put(out, c.unsampled);
      put(out, c.parent);
      put(out, c.attach);
      put(out, c.born);
      put(out, c.ended);
      put(out, c.tree);
      put(out, c.type);
      put(out, c.order);
      put(out, c.status);
      put(out, c.evidence);
    }
    put<std::uint64_t>(out, a.trees.size());
    for (const Tree& t : a.trees) {
      put(out, t.type);
      put(out, t.born);
      put(out, t.growing);
      put_array(out, t.by_order);
    }
    put_array(out, a.growing);
    put_array(out, a.sums);
  }
}

std::vector<Arbour> read_arbours(const std::vector<std::uint8_t>& in) {
  Cursor c(in);
  const auto n = c.get<std::uint64_t>();
  if (n > in.size()) throw std::runtime_error("checkpoint: more arbours than bytes");
  std::vector<Arbour> out(n);
  for (Arbour& a : out) {
    c.get_array(a.point);
    c.get_array(a.cone_of);
    c.get_array(a.step_of);
    if (a.cone_of.size() != a.point.size() || a.step_of.size() != a.point.size())
      throw std::runtime_error("checkpoint: an arbour's point arrays differ in length");
    const auto cones = c.get<std::uint64_t>();
    if (cones > in.size()) throw std::runtime_error("checkpoint: more cones than bytes");
    a.cones.resize(cones);
    for (Cone& k : a.cones) {
      k.tip = c.get<core::Vec3>();
      k.heading = c.get<core::Vec3>();
      k.rate = c.get<double>();
      k.length = c.get<double>();
      k.unsampled = c.get<double>();
      k.parent = c.get<std::uint32_t>();
      k.attach = c.get<std::uint32_t>();
      k.born = c.get<std::uint32_t>();
      k.ended = c.get<std::uint32_t>();
      k.tree = c.get<std::uint16_t>();
      k.type = c.get<std::uint8_t>();
      k.order = c.get<std::uint8_t>();
      k.status = c.get<ConeStatus>();
      const auto evidence = c.get<std::uint8_t>();
      if (evidence > 1) throw std::runtime_error("checkpoint: a cone's evidence flag is not 0 or 1");
      k.evidence = evidence == 1;
    }
    const auto trees = c.get<std::uint64_t>();
    if (trees > in.size()) throw std::runtime_error("checkpoint: more trees than bytes");
    a.trees.resize(trees);
    for (Tree& t : a.trees) {
      t.type = c.get<std::uint8_t>();
      t.born = c.get<std::uint32_t>();
      t.growing = c.get<int>();
      c.get_array(t.by_order);
    }
    c.get_array(a.growing);
    c.get_array(a.sums);
    for (const std::uint32_t k : a.cone_of)
      if (k >= a.cones.size()) throw std::runtime_error("checkpoint: a point of a cone that does not exist");
    for (const std::uint32_t k : a.growing)
      if (k >= a.cones.size()) throw std::runtime_error("checkpoint: a growing cone that does not exist");
    for (const Cone& k : a.cones)
      if (k.tree >= a.trees.size() || (k.parent != kNoCone && k.parent >= a.cones.size()) ||
          (k.attach != kNoPoint && (k.attach >= a.point.size() || a.cone_of[k.attach] != k.parent)))
        throw std::runtime_error("checkpoint: a cone of a tree, parent or branch point that does not exist");
    link_cones(a);
  }
  if (!c.done()) throw std::runtime_error("checkpoint: bytes after the arbours");
  return out;
}

}  // namespace axg::morphology
