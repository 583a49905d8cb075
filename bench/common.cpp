#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "bench.hpp"

namespace axg::bench {

std::string format_row(const Row& r) {
  const std::string what =
      fmt::format("{:<11} {:<46} {:<40} {:>2} thr  n={:<9.3g}", r.group, r.name, r.impl, r.threads, r.size);
  if (r.failed || r.seconds <= 0) return what + " " + r.note;
  const std::string ratio = r.ratio > 0 ? fmt::format("{:8.2f}x vs {}", r.ratio, r.baseline) : "";
  return fmt::format("{} {:>10.4f} s  {:>10.3g} {:<13} {}{}", what, r.seconds, r.rate, r.unit, ratio,
                     r.note.empty() ? "" : "  (" + r.note + ")");
}

Row failed_row(std::string group, std::string name, std::string impl, int threads, double size, std::string unit,
               std::string why) {
  Row r{std::move(group), std::move(name), std::move(impl), threads, size, 0, 0, std::move(unit), 0, "",
        "FAILED: " + why};
  r.failed = true;
  return r;
}

double time_median(const std::function<void()>& fn, int repeats, double budget_seconds) {
  std::vector<double> t;
  double spent = 0;
  for (int k = 0; k < repeats && (k == 0 || spent < budget_seconds); ++k) {
    const auto a = std::chrono::steady_clock::now();
    fn();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
    t.push_back(s);
    spent += s;
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

Paired time_paired(const std::function<void()>& peer, const std::function<void()>& ours, int rounds) {
  auto once = [](const std::function<void()>& fn) {
    const auto a = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  };
  once(peer);  // warm-up: page faults, caches, thread start
  once(ours);
  std::vector<double> tp, to, ratio;
  for (int k = 0; k < rounds; ++k) {
    tp.push_back(once(peer));
    to.push_back(once(ours));
    ratio.push_back(tp.back() / to.back());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  return {median(tp), median(to), median(ratio)};
}

Scene paper_direct_scene(std::uint64_t neurons) {
  Scene s;
  s.neurons.count = neurons;
  s.neurons.radius = std::round(2.5 * std::cbrt(static_cast<double>(neurons) / 100.0) * 1e4) / 1e4;
  s.guidance.model = GuidanceModel::kDirect;
  s.guidance.decision = DecisionRule::kPerStep;  // the report's rule (no cue turns here)
  s.steps = 100;
  s.axons.persistence_length.reset();  // the report's straight axons
  return s;
}

Scene paper_cue_scene(std::uint64_t neurons) {
  // The built-in scene's cues (two attractants, two repellents, particles, SNR) at the
  // report's Table 5 setting.
  Scene s = Scene::builtin_default();
  s.neurons.count = neurons;
  s.neurons.radius = 2.5;
  s.neurons.soma_radius = std::round(2.5 * std::cbrt(0.1 / static_cast<double>(neurons)) * 1e4) / 1e4;
  s.steps = 100;
  s.axons.persistence_length.reset();  // the report's straight axons
  s.guidance.decision = DecisionRule::kPerStep;  // the report's one turn per step,
  s.guidance.noise = NoiseForm::kBinding;  // the report's SNR form,
  s.cues.particles.amount = 0.01;          // particle amount and emission
  s.cues.warmup_steps = 0;                 // and fields that start empty
  for (auto& src : s.cues.sources) src.emission = 100;
  return s;
}

}  // namespace axg::bench
