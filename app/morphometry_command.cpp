// `axonguide morphometry DIR`: the morphometric statistics of Ramakers' culture data for a
// run's morphologies/ or a folder of SWC files made elsewhere (docs/methods.md §13).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/support/files.hpp"
#include "axonguide/morphology/morphometry.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/validate/report.hpp"
#include "commands.hpp"

namespace axg::app {

namespace fs = std::filesystem;

namespace {

// A number in shortest round-trip form; NaN (a mean of nothing, an sd of one) as "nan".
std::string num(double v) { return std::isnan(v) ? "nan" : fmt::format("{}", v); }

}  // namespace

int cmd_morphometry(const MorphometryArgs& args) {
  using namespace morphology;
  if (args.projection != "none" && args.projection != "xy")
    throw InputError(fmt::format("morphometry --projection {}: not in {{none, xy}}", args.projection));
  if (!(args.sholl_step > 0) || !std::isfinite(args.sholl_step))
    throw InputError(fmt::format("morphometry --sholl-step {}: must be a finite number > 0 (µm)", args.sholl_step));
  const Projection p = args.projection == "xy" ? Projection::kXY : Projection::kNone;
  const std::vector<Morphology> ms = read_folder(args.dir);  // every file checked before anything is written
  const fs::path out = args.out.empty() ? fs::path(args.dir) : fs::path(args.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw InputError(fmt::format("morphometry --out {}: is a file", out.string()));
  create_output_dir(out);

  std::vector<NeuronStats> stats;
  for (const auto& m : ms) stats.push_back(measure(m, p));

  std::string pop = "statistic,n,mean,sd,se\n";
  for (const Row& r : population(stats))
    pop += fmt::format("{},{},{},{},{}\n", r.statistic, r.n, num(r.mean), num(r.sd), num(r.se));
  std::string per = "neuron,has_axon,total_axon_length,branch_points_per_axon,terminal_segments_per_axon,"
                    "axons_mean_terminal_segment_length,axons_mean_intermediate_segment_length,"
                    "number_of_dendrites_per_neuron\n";
  std::string dend = "neuron,dendrite,total_dendrite_length,branch_points_per_dendrite,terminal_segments_per_dendrite,"
                     "dendrites_mean_terminal_segment_length,dendrites_mean_intermediate_segment_length\n";
  for (const NeuronStats& n : stats) {
    const auto& a = n.axon;
    per += fmt::format("{},{},{},{},{},{},{},{}\n", n.name, n.has_axon ? 1 : 0, n.has_axon ? num(a.total_length) : "nan",
                       n.has_axon ? std::to_string(a.branch_points) : "nan",
                       n.has_axon ? std::to_string(a.terminal_segments) : "nan",
                       n.has_axon ? num(a.mean_terminal_segment_length) : "nan",
                       n.has_axon ? num(a.mean_intermediate_segment_length) : "nan", n.dendrites.size());
    for (std::size_t k = 0; k < n.dendrites.size(); ++k) {
      const auto& d = n.dendrites[k];
      dend += fmt::format("{},{},{},{},{},{},{}\n", n.name, k, num(d.total_length), d.branch_points,
                          d.terminal_segments, num(d.mean_terminal_segment_length),
                          num(d.mean_intermediate_segment_length));
    }
  }
  // Sholl: per radius, the mean over neurons (every neuron, 0 beyond its reach) with sd and se.
  std::vector<std::vector<int>> sa, sd;
  std::size_t radii = 0;
  for (const auto& m : ms) {
    sa.push_back(sholl(m, 2, args.sholl_step, p));
    sd.push_back(sholl(m, 3, args.sholl_step, p));
    radii = std::max<std::size_t>({radii, sa.back().size(), sd.back().size()});
  }
  std::string sh = "radius,axon_mean,axon_sd,axon_se,dendrite_mean,dendrite_sd,dendrite_se,neurons\n";
  const double n = static_cast<double>(ms.size());
  for (std::size_t k = 0; k < radii; ++k) {
    double mean[2], sdv[2];
    for (int g = 0; g < 2; ++g) {
      const auto& v = g == 0 ? sa : sd;
      double s = 0;
      for (const auto& x : v) s += k < x.size() ? x[k] : 0;
      mean[g] = s / n;
      double ss = 0;
      for (const auto& x : v) {
        const double d = (k < x.size() ? x[k] : 0) - mean[g];
        ss += d * d;
      }
      sdv[g] = ms.size() > 1 ? std::sqrt(ss / (n - 1)) : std::nan("");
    }
    sh += fmt::format("{},{},{},{},{},{},{},{}\n", num(args.sholl_step * static_cast<double>(k + 1)), num(mean[0]),
                      num(sdv[0]), num(sdv[0] / std::sqrt(n)), num(mean[1]), num(sdv[1]), num(sdv[1] / std::sqrt(n)),
                      ms.size());
  }
  write_file_atomically(out, "morphometry.csv", pop);
  write_file_atomically(out, "morphometry_neurons.csv", per);
  write_file_atomically(out, "morphometry_dendrites.csv", dend);
  write_file_atomically(out, "sholl.csv", sh);
  const bool drawn = validate::draw_folder_plot(out, "morphometry.py", "morphometry.png", "morphometry");
  fmt::print("morphometry {} morphologies ({} with an axon), projection {}\n", ms.size(),
             std::count_if(stats.begin(), stats.end(), [](const NeuronStats& s) { return s.has_axon; }),
             args.projection);
  fmt::print("outputs   {}/morphometry.csv, morphometry_neurons.csv, morphometry_dendrites.csv, sholl.csv{}\n",
             out.string(), drawn ? ", morphometry.png" : "");
  return kExitOk;
}

}  // namespace axg::app
