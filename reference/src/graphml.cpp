// graph.graphml through Boost.Graph's write_graphml, from a compressed sparse row graph
// (a few bytes per vertex, so a million-neuron network stays cheap to write).
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/graphml.hpp>
#include <boost/property_map/dynamic_property_map.hpp>
#include <boost/property_map/function_property_map.hpp>

#include <ostream>
#include <streambuf>

#include "axonguide/output.hpp"
#include "axonguide/run.hpp"
#include "axonguide/scene.hpp"

namespace axg {

namespace {

// std::ostream onto an AtomicFile.
class FileBuf : public std::streambuf {
 public:
  explicit FileBuf(AtomicFile& f) : f_(f) { setp(buf_, buf_ + sizeof buf_); }
  ~FileBuf() override { sync(); }

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

struct EdgeData {
  std::uint32_t step;
  double length;
};

}  // namespace

void write_graphml(const RunResult& r, AtomicFile& file) {
  using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeData,
                                                   boost::no_property, std::uint32_t, std::uint32_t>;
  const std::size_t n = r.neurons.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<EdgeData> data;
  for (std::size_t i = 0; i < n; ++i)
    if (r.neurons.target[i] != core::kNoNeuron) {
      edges.emplace_back(static_cast<std::uint32_t>(i), r.neurons.target[i]);
      data.push_back({r.neurons.steps[i], r.neurons.length[i]});
    }
  Graph g(boost::edges_are_sorted, edges.begin(), edges.end(), data.begin(), n);

  using Vertex = Graph::vertex_descriptor;
  boost::dynamic_properties dp;
  auto soma = [&](int axis) {
    return boost::make_function_property_map<Vertex, double>([&r, axis](Vertex v) {
      const core::Vec3& p = r.soma[v];
      return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
    });
  };
  dp.property("x", soma(0));
  dp.property("y", soma(1));
  dp.property("z", soma(2));
  dp.property("status", boost::make_function_property_map<Vertex, std::string>(
                            [&r](Vertex v) { return std::string(name_of(r.neurons.status[v])); }));
  if (r.graph.bfs)
    dp.property("level", boost::make_function_property_map<Vertex, int>(
                             [&r](Vertex v) { return static_cast<int>(r.graph.bfs->level[v]); }));
  if (!r.graph.component.empty())
    dp.property("component", boost::make_function_property_map<Vertex, long>(
                                 [&r](Vertex v) { return static_cast<long>(r.graph.component[v]); }));
  dp.property("step", get(&EdgeData::step, g));
  dp.property("length", get(&EdgeData::length, g));

  FileBuf buf(file);
  std::ostream os(&buf);
  boost::write_graphml(os, g, dp, true);
  os.flush();
}

}  // namespace axg
