// SWC morphologies (docs/methods.md §4.3). Each file is a pure function of the run: numbers
// in their shortest round-trip form, the soma first, the axon's points in step order.
#include "axonguide/io/swc.hpp"

#include <fmt/format.h>

#include <tbb/parallel_for.h>

#include "axonguide/io/canonical_nan.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

namespace fs = std::filesystem;

namespace {

// An arbour: the soma, then every cone's points in cone order (morphology::samples), each
// with its type (2 axon, 3 dendrite) and the radius of its neurite type at its centrifugal
// order (diameter x taper^order / 2).
std::string arbour_swc_text(const RunResult& r, std::size_t i, SwcFrame frame) {
  const double um = r.scene.units.micrometres();
  const ArbourKeys& k = *r.scene.arbours;
  double radius[2][256];
  for (int t = 0; t < 2; ++t) {
    const NeuriteKeys& n = t == 0 ? k.axon : k.dendrites;
    double d = n.diameter;
    for (int o = 0; o < 256; ++o, d *= n.taper) radius[t][o] = 0.5 * d;
  }
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "# axonguide neuron {}: soma, then its arbour (axon 2, dendrites 3), cone by cone; micrometres\n", i);
  const bool centred = frame == SwcFrame::kSomaCentred;
  const core::Vec3 origin = centred ? r.soma[i] : core::Vec3{0, 0, 0};
  const core::Vec3 soma = canonical(r.soma[i] - origin);
  fmt::format_to(out, "1 1 {} {} {} {} -1\n", soma.x * um, soma.y * um, soma.z * um,
                 canonical(r.scene.neurons.soma_radius) * um);
  const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(r.arbours[i]);
  for (std::size_t j = 0; j < s.size(); ++j) {
    const core::Vec3 p = canonical(s[j].pos - origin);
    fmt::format_to(out, "{} {} {} {} {} {} {}\n", j + 2, s[j].type, p.x * um, p.y * um, p.z * um,
                   radius[s[j].type == morphology::kAxonType ? 0 : 1][s[j].order], s[j].parent);
  }
  return fmt::to_string(b);
}

}  // namespace

std::string swc_text(const RunResult& r, std::size_t i, SwcFrame frame) {
  if (r.scene.arbours) return arbour_swc_text(r, i, frame);
  const double um = r.scene.units.micrometres();
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "# axonguide neuron {} ({}): soma, then the axon's tip after each step; micrometres\n", i,
                 name_of(r.neurons.status[i]));
  const core::Vec3 soma = canonical(r.soma[i]);
  fmt::format_to(out, "1 1 {} {} {} {} -1\n", soma.x * um, soma.y * um, soma.z * um,
                 canonical(r.scene.neurons.soma_radius) * um);
  const std::size_t last = std::min<std::size_t>(r.neurons.steps[i], r.paths.empty() ? 0 : r.paths.size() - 1);
  if (r.neurons.length[i] > 0 && !r.paths.empty())
    for (std::size_t s = 0; s <= last; ++s) {
      const core::Vec3 p = canonical(r.paths[s][i]);
      fmt::format_to(out, "{} 2 {} {} {} {} {}\n", s + 2, p.x * um, p.y * um, p.z * um, kSwcAxonRadiusUm, s + 1);
    }
  return fmt::to_string(b);
}

namespace {

void write_swc_files(const RunResult& r, const fs::path& dir, const std::string& sub, SwcFrame frame,
                     OutputInfo& info) {
  const fs::path mdir = dir / sub;
  create_output_dir(mdir);
  const std::size_t n = r.neurons.size();
  std::vector<std::string> hashes(n);
  // Many small files: each is renamed into place unsynced, and the file system is synced
  // once before their hashes are recorded (and the manifest names them).
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    AtomicFile f(mdir, fmt::format("{}.swc", i), AtomicFile::Sync::kDeferred);
    f.write(swc_text(r, i, frame));
    hashes[i] = f.commit();
  });
  sync_filesystem(mdir);
  for (std::size_t i = 0; i < n; ++i) info.files.emplace_back(fmt::format("{}/{}.swc", sub, i), std::move(hashes[i]));
}

}  // namespace

void write_swc(const RunResult& r, const fs::path& dir, OutputInfo& info) {
  write_swc_files(r, dir, "morphologies", SwcFrame::kAbsolute, info);
}

void write_centred_swc(const RunResult& r, const fs::path& dir, const std::string& sub, OutputInfo& info) {
  write_swc_files(r, dir, sub, SwcFrame::kSomaCentred, info);
}

}  // namespace axg
