// graph.graphml through Boost.Graph's write_graphml, from a compressed sparse row graph
// (a few bytes per vertex, so a million-neuron network stays cheap to write).
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/graphml.hpp>
#include <boost/property_map/dynamic_property_map.hpp>

#include <fmt/format.h>

#include <ostream>
#include <stdexcept>
#include <type_traits>
#include <typeinfo>
#include <streambuf>

#include "axonguide/io/canonical_nan.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

namespace {

// std::ostream onto an AtomicFile. The stream must be flushed by its user: the destructor
// writes nothing, because a write can throw (a full disk) and a destructor must not. The
// stream is to rethrow the AtomicFile's RunError (exceptions(badbit)); the AtomicFile keeps
// the failure in any case, so its commit() throws it too.
class FileBuf : public std::streambuf {
 public:
  explicit FileBuf(AtomicFile& f) : f_(f) { setp(buf_, buf_ + sizeof buf_); }

 protected:
  int_type overflow(int_type ch) override {
    sync();
    if (ch != traits_type::eof()) {
      *pptr() = static_cast<char>(ch);
      pbump(1);
    }
    return ch;
  }
  int sync() override {
    f_.write(std::string_view(pbase(), static_cast<std::size_t>(pptr() - pbase())));
    setp(buf_, buf_ + sizeof buf_);
    return 0;
  }

 private:
  AtomicFile& f_;
  char buf_[1 << 16];
};

// A read-only dynamic property whose strings are fmt's shortest round-trip form: Boost's
// own adaptor prints through an ostringstream at the default 6 significant digits, which
// loses precision (and is slow). value() still reports T, so the GraphML key declares
// the right attr.type. A NaN is written "nan" (canonical()), whatever its sign or payload.
template <class Key, class T, class Fn>
class ExactProperty final : public boost::dynamic_property_map {
 public:
  explicit ExactProperty(Fn fn) : fn_(std::move(fn)) {}
  boost::any get(const boost::any& key) override { return fn_(boost::any_cast<Key>(key)); }
  std::string get_string(const boost::any& key) override {
    if constexpr (std::is_same_v<T, double>) return fmt::format("{}", canonical(fn_(boost::any_cast<Key>(key))));
    else return fmt::format("{}", fn_(boost::any_cast<Key>(key)));
  }
  void put(const boost::any&, const boost::any&) override {
    throw std::logic_error("graphml properties are read-only");
  }
  const std::type_info& key() const override { return typeid(Key); }
  const std::type_info& value() const override { return typeid(T); }

 private:
  Fn fn_;
};

template <class Key, class T, class Fn>
void add_property(boost::dynamic_properties& dp, const std::string& name, Fn fn) {
  dp.insert(name, boost::shared_ptr<boost::dynamic_property_map>(new ExactProperty<Key, T, Fn>(std::move(fn))));
}

struct EdgeData {
  std::uint32_t step;  // a synapse scene: the connection's first step
  double length;       // the axon's length (no synapses) or the connection's synapse count
};

}  // namespace

void write_graphml(const RunResult& r, AtomicFile& file) {
  using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeData,
                                                   boost::no_property, std::uint32_t, std::uint32_t>;
  const std::size_t n = r.neurons.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<EdgeData> data;
  const bool synapses = r.scene.synapses.has_value();
  if (synapses)
    for (const network::Connection& c : r.synapse_connections) {
      edges.emplace_back(c.source, c.target);
      data.push_back({c.first_step, static_cast<double>(c.synapses)});
    }
  else
    for (std::size_t i = 0; i < n; ++i)
      if (r.neurons.target[i] != core::kNoNeuron) {
        edges.emplace_back(static_cast<std::uint32_t>(i), r.neurons.target[i]);
        data.push_back({r.neurons.steps[i], r.neurons.length[i]});
      }
  Graph g(boost::edges_are_sorted, edges.begin(), edges.end(), data.begin(), n);

  using Vertex = Graph::vertex_descriptor;
  using Edge = Graph::edge_descriptor;
  boost::dynamic_properties dp;
  add_property<Vertex, double>(dp, "x", [&r](Vertex v) { return r.soma[v].x; });
  add_property<Vertex, double>(dp, "y", [&r](Vertex v) { return r.soma[v].y; });
  add_property<Vertex, double>(dp, "z", [&r](Vertex v) { return r.soma[v].z; });
  add_property<Vertex, std::string>(dp, "status",
                                    [&r](Vertex v) { return std::string(name_of(r.neurons.status[v])); });
  if (r.graph.bfs)
    add_property<Vertex, int>(dp, "level", [&r](Vertex v) { return static_cast<int>(r.graph.bfs->level[v]); });
  if (!r.graph.component.empty())
    add_property<Vertex, long>(dp, "component",
                               [&r](Vertex v) { return static_cast<long>(r.graph.component[v]); });
  add_property<Edge, int>(dp, "step", [&g](Edge e) { return static_cast<int>(g[e].step); });
  if (synapses)  // the weight is the connection's realised synapse count
    add_property<Edge, int>(dp, "weight", [&g](Edge e) { return static_cast<int>(g[e].length); });
  else
    add_property<Edge, double>(dp, "length", [&g](Edge e) { return g[e].length; });

  FileBuf buf(file);
  std::ostream os(&buf);
  os.exceptions(std::ios::badbit);  // the RunError of a failed write, not a silent badbit
  boost::write_graphml(os, g, dp, true);
  os.flush();
}

}  // namespace axg
