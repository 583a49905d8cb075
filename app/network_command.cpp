// `axonguide network DIR`: the network's statistics of a run (docs/methods.md §2.13):
// network.csv, degrees.csv, synapses_per_connection.csv, connection_probability.csv and a plot.
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/io/csv.hpp"
#include "axonguide/io/neurons_csv.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/network/statistics.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/validate/report.hpp"
#include "commands.hpp"

namespace axg::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// connections.csv: a synapse scene's (source,target,synapses,first_step) or a soma-contact
// run's (source,target,step,length: one synapse a connection). Sorted by source then target,
// ids below n, no pair twice; anything else is exit 2 naming the line.
std::vector<network::Edge> read_connections(const std::string& text, const std::string& where, std::size_t n) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const bool synapses = trim_cell(line) == "source,target,synapses,first_step";
  if (!synapses && trim_cell(line) != "source,target,step,length")
    throw InputError(fmt::format("{}: line 1: header \"{}\": not a run's connections.csv", where, line));
  std::vector<network::Edge> out;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    auto id = [&](std::size_t k) {
      const auto v = k < cells.size() ? parse_number(cells[k]) : std::nullopt;
      if (!v || !(*v >= 0) || *v != std::floor(*v) || *v >= static_cast<double>(n))
        throw InputError(fmt::format("{}: line {}: field {} is not a neuron id below {}: not a run's data", where, number,
                                     k + 1, n));
      return static_cast<std::uint32_t>(*v);
    };
    if (cells.size() != 4)
      throw InputError(fmt::format("{}: line {}: {} fields, not 4: not a run's data", where, number, cells.size()));
    network::Edge e{id(0), id(1), 1};
    if (synapses) {
      const auto v = parse_number(cells[2]);
      if (!v || !(*v >= 1) || *v != std::floor(*v) || *v > 4294967295.0)
        throw InputError(fmt::format("{}: line {}: synapses \"{}\" is not a count >= 1", where, number, cells[2]));
      e.synapses = static_cast<std::uint32_t>(*v);
    }
    if (!out.empty() && (e.source < out.back().source || (e.source == out.back().source && e.target <= out.back().target)))
      throw InputError(fmt::format("{}: line {}: ({}, {}) after ({}, {}): not sorted by source then target, or a pair "
                                   "twice",
                                   where, number, e.source, e.target, out.back().source, out.back().target));
    out.push_back(e);
  }
  return out;
}

std::string num(double v) { return std::isnan(v) ? "nan" : fmt::format("{}", v); }

// Wilson's 95 % interval of k successes in n trials.
std::pair<double, double> wilson(std::uint64_t k, std::uint64_t n) {
  if (n == 0) return {std::nan(""), std::nan("")};
  const double z = 1.959963984540054, p = static_cast<double>(k) / static_cast<double>(n), nn = static_cast<double>(n);
  const double c = (p + z * z / (2 * nn)) / (1 + z * z / nn);
  const double h = z / (1 + z * z / nn) * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn));
  return {k == 0 ? 0.0 : std::max(0.0, c - h), k == n ? 1.0 : std::min(1.0, c + h)};
}

}  // namespace

int cmd_network(const NetworkArgs& args) {
  if (!(args.bin > 0) || !std::isfinite(args.bin))
    throw InputError(fmt::format("network --bin {}: must be a finite number > 0 (µm)", args.bin));
  const fs::path dir(args.dir);
  if (!fs::is_directory(dir)) throw InputError(fmt::format("network: {} is not a directory", args.dir));
  const json manifest = require_whole_run(dir, "network");
  for (const char* f : {"neurons.csv", "connections.csv"})
    if (!manifest["files"].contains(f))
      throw InputError(fmt::format("network: {}/manifest.json does not list {} (output.csv false?)", args.dir, f));
  if (!manifest.contains("scene"))
    throw InputError(fmt::format("network: {}/manifest.json holds no scene: not a run's manifest", args.dir));
  const Scene scene = parse_scene(manifest["scene"].dump(), args.dir + "/manifest.json scene").scene;
  const NeuronRows rows = read_neurons_csv(read_file(dir / "neurons.csv", "network"),
                                           fmt::format("network: {}", (dir / "neurons.csv").string()), scene.neurons.count);
  const std::vector<network::Edge> edges = read_connections(
      read_file(dir / "connections.csv", "network"), fmt::format("network: {}", (dir / "connections.csv").string()), rows.size());
  const double um = scene.units.micrometres();
  const network::NetworkStats s = network::network_stats(rows.soma, edges, args.bin / um);

  const fs::path out = args.out.empty() ? dir : fs::path(args.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw InputError(fmt::format("network --out {}: is a file", out.string()));
  create_output_dir(out);
  const double n = static_cast<double>(s.neurons);
  std::string summary = "statistic,value\n";
  auto put = [&](const char* name, double v) { summary += fmt::format("{},{}\n", name, num(v)); };
  put("neurons", n);
  put("connections", static_cast<double>(s.connections));
  put("synapses", static_cast<double>(s.synapses));
  put("mean_out_degree", n > 0 ? static_cast<double>(s.connections) / n : std::nan(""));
  put("mean_synapses_per_connection",
      s.connections > 0 ? static_cast<double>(s.synapses) / static_cast<double>(s.connections) : std::nan(""));
  put("connection_probability", n > 1 ? static_cast<double>(s.connections) / (n * (n - 1)) : std::nan(""));
  put("reciprocity", s.reciprocity);
  put("clustering", s.clustering);
  put("mean_path_length", s.mean_path_length);
  put("reachable_pairs", s.reachable);
  put("path_sources", static_cast<double>(s.path_sources));
  std::string degrees = "degree,out_neurons,in_neurons\n";
  for (std::size_t k = 0; k < std::max(s.out_degree.size(), s.in_degree.size()); ++k)
    degrees += fmt::format("{},{},{}\n", k, k < s.out_degree.size() ? s.out_degree[k] : 0,
                           k < s.in_degree.size() ? s.in_degree[k] : 0);
  std::string per = "synapses,connections\n";
  for (std::size_t k = 1; k < s.synapses_per_connection.size(); ++k)
    per += fmt::format("{},{}\n", k, s.synapses_per_connection[k]);
  std::string prob = "distance_lo_um,distance_hi_um,pairs,connected,probability,ci_lo,ci_hi\n";
  for (const network::DistanceBin& b : s.distance) {
    const auto [lo, hi] = wilson(b.connected, b.pairs);
    prob += fmt::format("{},{},{},{},{},{},{}\n", num(b.lo * um), num(b.hi * um), b.pairs, b.connected,
                        b.pairs ? num(static_cast<double>(b.connected) / static_cast<double>(b.pairs)) : "nan", num(lo),
                        num(hi));
  }
  write_file_atomically(out, "network.csv", summary);
  write_file_atomically(out, "degrees.csv", degrees);
  write_file_atomically(out, "synapses_per_connection.csv", per);
  write_file_atomically(out, "connection_probability.csv", prob);
  const bool drawn = validate::draw_folder_plot(out, "network.py", "network.png", "network");
  fmt::print("network   {} neurons, {} connections, {} synapses; reciprocity {:.4f}, clustering {:.4f}, mean path "
             "length {:.3f} ({:.1f}% of pairs reachable, {} sources)\n",
             s.neurons, s.connections, s.synapses, s.reciprocity, s.clustering, s.mean_path_length, 100.0 * s.reachable,
             s.path_sources);
  fmt::print("outputs   {}/network.csv, degrees.csv, synapses_per_connection.csv, connection_probability.csv{}\n",
             out.string(), drawn ? ", network.png" : "");
  return kExitOk;
}

}  // namespace axg::app
