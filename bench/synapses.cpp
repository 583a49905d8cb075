// Synapses (issue 42): the bench culture of `bench arbours` (scenes/culture.json's density,
// arbours twice the data's 5-day size, dt 0.5 h, its sample length of 4 um) with apposition
// detection at d = 2 um, no SWC.
//  - End to end in a child process (placement, growth, detection, the CSV files; its own
//    peak memory) at 10^4 neurons (goal <= 15 s on 2 cores) and 10^5 (<= 3 min, <= 8 GB).
//  - Contacts and appositions per second of detection, and detection's share of the run.
//  - Detection alone at three sizes of one density: seconds per segment, which is flat
//    when the cost is O(segments).
//  - The same 10^4 culture recorded at a sample length of 1 um (validate synapses §D:
//    appositions within about 3 % of their limit), for the cost of that accuracy.
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/network/appositions.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/threads.hpp"
#include "bench.hpp"

namespace axg::bench {

namespace {

Scene synapse_scene(std::uint64_t neurons) {
  Scene s = arbour_benchmark_scene(neurons);
  s.output.swc = false;
  s.synapses = SynapseKeys{};
  s.synapses->distance = 2.0;
  s.analysis.bfs_sources.clear();
  s.analysis.components = false;
  return s;
}

}  // namespace

std::vector<Row> synapses(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int threads = resolve_threads(o.max_threads);
  const std::string group = "synapses";
  // End to end.
  std::vector<std::uint64_t> sizes{o.quick ? 1000u : 10000u};
  if (!o.quick) sizes.push_back(100000);
  for (const std::uint64_t n : sizes)
    for (const double sample : n == 10000 ? std::vector<double>{4.0, 1.0} : std::vector<double>{4.0}) {
      Scene s = synapse_scene(n);
      s.arbours->sample_length = sample;
      const std::string name =
          fmt::format("synapses, culture x2 size ({} neurons, 5 days, dt 0.5 h, sample length {} um, d = 2 um)", n, sample);
      const ChildRun c = run_child(s, threads, "reference");
      if (c.status != 0 || c.manifest.is_null()) {
        emit(failed_row(group, name + ": end to end", "axonguide reference", threads, double(n), "neurons/s",
                        fmt::format("the run exited {}", c.status)));
        continue;
      }
      const auto& m = c.manifest;
      const double detect = m["timings_seconds"].value("synapses", 0.0);
      const double contacts = m["summary"].value("contacts", 0.0), apps = m["summary"].value("appositions", 0.0);
      emit({group, name + ": end to end", "axonguide reference", threads, double(n), c.seconds,
            double(n) / c.seconds, "neurons/s", 0, "",
            fmt::format("peak memory {:.2f} GB; {:.0f} contacts, {:.0f} appositions, {:.0f} connections; detection "
                        "{:.2f} s ({:.0f} % of the run)",
                        c.peak_bytes / 1e9, contacts, apps, m["summary"].value("synaptic_connections", 0.0), detect,
                        100.0 * detect / c.seconds)});
      emit({group, name + ": detection, contacts", "axonguide reference", threads, contacts, detect, contacts / detect,
            "contacts/s", 0, "", ""});
      emit({group, name + ": detection, appositions", "axonguide reference", threads, apps, detect, apps / detect,
            "appositions/s", 0, "", ""});
    }
  // Detection alone at three sizes of one density.
  const std::vector<std::uint64_t> scaling = o.quick ? std::vector<std::uint64_t>{500, 1000, 2000}
                                                     : std::vector<std::uint64_t>{2500, 5000, 10000};
  double first = 0;
  for (const std::uint64_t n : scaling) {
    const Scene s = synapse_scene(n);
    RunResult r;
    try {
      Scene grown = s;
      grown.synapses.reset();  // grow only; detection is timed below
      RunOptions ro;
      r = with_threads(threads, [&] { return run_scene(grown, ro); });
    } catch (const std::exception& e) {
      emit(failed_row(group, "detection alone", "axonguide reference", threads, double(n), "segments/s", e.what()));
      continue;
    }
    const SynapseParams p = synapse_params(s);
    std::size_t segments = 0, contacts = 0, apps = 0;
    const double seconds = time_median(
        [&] {
          with_threads(threads, [&] {
            const network::Segments g = network::segments_of(r.arbours, r.soma, s.neurons.soma_radius);
            segments = g.size();
            std::uint64_t found = 0;
            apps = network::find_appositions(g, p, &found).size();
            contacts = found;
            return 0;
          });
        },
        3, 1.0);
    const double per = seconds / static_cast<double>(segments);
    if (first == 0) first = per;
    emit({group, fmt::format("detection alone, {} neurons at the culture's density", n), "axonguide reference", threads,
          double(segments), seconds, double(segments) / seconds, "segments/s", 0, "",
          fmt::format("{:.0f} contacts, {:.0f} appositions; {:.3g} ns per segment, {:.2f}x the smallest size's", double(contacts),
                      double(apps), per * 1e9, per / first)});
  }
  return rows;
}

}  // namespace axg::bench
