#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/info.h>

#include "axonguide/error.hpp"
#include "axonguide/version.hpp"
#include "backend.hpp"
#include "bench.hpp"
#include "commands.hpp"

namespace axg::app {

namespace {

void print_row(const bench::Row& r) {
  std::string ratio = r.ratio > 0 ? fmt::format("{:8.2f}x vs {}", r.ratio, r.baseline) : "";
  fmt::print("{:<11} {:<46} {:<40} {:>2} thr  n={:<9.3g} {:>10.4f} s  {:>10.3g} {:<13} {}{}\n", r.group, r.name, r.impl,
             r.threads, r.size, r.seconds, r.rate, r.unit, ratio, r.note.empty() ? "" : "  (" + r.note + ")");
  std::fflush(stdout);
}

}  // namespace

int cmd_bench(const BenchArgs& args) {
  bench::Options o;
  o.quick = args.quick;
  o.max_threads = args.threads;
  o.backend = args.backend;
  o.make_engine = engine_factory(args.backend);
  if (!args.json) {
    fmt::print("axonguide {} ({}) bench {}{}, {} hardware threads\n", kVersion, kCommit, args.what,
               args.quick ? " --quick" : "", tbb::info::default_concurrency());
    o.on_row = print_row;
  }
  std::vector<bench::Row> rows;
  auto add = [&](std::vector<bench::Row> more) { rows.insert(rows.end(), more.begin(), more.end()); };
  const std::string& w = args.what;
  if (w == "samplers" || w == "all") add(bench::samplers(o));
  if (w == "growth" || w == "all") add(bench::growth(o));
  if (w == "particles" || w == "all") add(bench::particles(o));
  if (w == "grid" || w == "all") add(bench::grid(o));
  if (w == "bfs" || w == "all") add(bench::bfs(o));
  if (args.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows)
      j.push_back({{"group", r.group}, {"name", r.name}, {"impl", r.impl}, {"threads", r.threads}, {"size", r.size},
                   {"seconds", r.seconds}, {"rate", r.rate}, {"unit", r.unit}, {"ratio", r.ratio},
                   {"baseline", r.baseline}, {"note", r.note}});
    fmt::print("{}\n", nlohmann::json{{"version", kVersion}, {"commit", kCommit}, {"rows", j}}.dump(2));
  }
  return kExitOk;
}

}  // namespace axg::app
