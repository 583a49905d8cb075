// neurons.csv read back: the one reader (view, assay), as strict as the writer is exact.
#include "axonguide/io/neurons_csv.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "axonguide/io/csv.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

NeuronRows read_neurons_csv(const std::string& text, const std::string& where, std::optional<std::size_t> expected) {
  NeuronRows out;
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);  // the header
  std::size_t row = 1;
  while (std::getline(lines, line)) {
    ++row;
    if (line.empty() || line == "\r") continue;
    auto refuse = [&](const std::string& why) {
      throw InputError(fmt::format("{}: line {}: {}: not a run's data", where, row, why));
    };
    const std::vector<std::string> f = split_csv_line(line);
    if (f.size() != 12) refuse(fmt::format("{} fields, where a run writes 12", f.size()));
    double v[12];
    for (std::size_t k = 0; k < 12; ++k) {
      if (k == 5) continue;  // the status
      const std::optional<double> x = parse_number(f[k]);
      if (!x || !std::isfinite(*x)) refuse(fmt::format("field {} (\"{}\") is not finite or not a number", k + 1, printable(f[k])));
      v[k] = *x;
    }
    const std::size_t i = out.size();
    if (v[0] != static_cast<double>(i)) refuse(fmt::format("id {} where {} belongs", printable(f[0]), i));
    if (!(v[4] > 0)) refuse("the soma radius is not a positive number");
    std::optional<core::AxonStatus> status;
    for (const auto s : {core::AxonStatus::kGrowing, core::AxonStatus::kConnected, core::AxonStatus::kExited,
                         core::AxonStatus::kMaxSteps})
      if (f[5] == name_of(s)) status = s;
    if (!status)
      refuse(fmt::format("status \"{}\" is not one of growing, connected, exited, max_steps", printable(f[5])));
    if (!(v[9] >= 0)) refuse("the length is negative");
    if (!(v[10] >= 0 && v[10] <= 4294967295.0 && v[10] == std::floor(v[10])))
      refuse(fmt::format("steps {} is not an integer in [0, 2^32)", printable(f[10])));
    if (!(v[11] == -1 || (v[11] >= 0 && v[11] == std::floor(v[11]) && v[11] < 4294967295.0)))
      refuse(fmt::format("target {} is not a neuron id or -1", printable(f[11])));
    out.soma.push_back({v[1], v[2], v[3]});
    out.soma_radius.push_back(v[4]);
    out.status.push_back(*status);
    out.tip.push_back({v[6], v[7], v[8]});
    out.length.push_back(v[9]);
    out.steps.push_back(static_cast<std::uint32_t>(v[10]));
    out.target.push_back(v[11] < 0 ? core::kNoNeuron : static_cast<std::uint32_t>(v[11]));
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    if (out.target[i] != core::kNoNeuron && out.target[i] >= out.size())
      throw InputError(fmt::format("{}: line {}: target {} is not a neuron id (0 to {}) or -1: not a run's data", where,
                                   i + 2, out.target[i], out.size() - 1));
  if (expected && out.size() != *expected)
    throw InputError(fmt::format("{}: {} neurons, where the run's scene has {}: not a run's data", where, out.size(),
                                 *expected));
  return out;
}

}  // namespace axg
