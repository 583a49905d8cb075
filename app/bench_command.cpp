#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/info.h>

#include <cstdio>

#include "axonguide/support/error.hpp"
#include "axonguide/version.hpp"
#include "backend.hpp"
#include "bench.hpp"
#include "commands.hpp"

namespace axg::app {

namespace {

void print_row(const bench::Row& r) {
  fmt::print("{}\n", bench::format_row(r));
  std::fflush(stdout);
}

}  // namespace

int cmd_bench(const BenchArgs& args) {
  require_backend(args.backend);  // before the first measurement
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
  if (w == "arbours" || w == "all") add(bench::arbours(o));
  if (w == "synapses" || w == "all") add(bench::synapses(o));
  if (args.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows) {
      const bool figure = !r.failed && r.seconds > 0;
      j.push_back({{"group", r.group}, {"name", r.name}, {"impl", r.impl}, {"threads", r.threads}, {"size", r.size},
                   {"seconds", figure ? nlohmann::json(r.seconds) : nlohmann::json()},
                   {"rate", figure ? nlohmann::json(r.rate) : nlohmann::json()}, {"unit", r.unit},
                   {"ratio", figure ? nlohmann::json(r.ratio) : nlohmann::json()}, {"baseline", r.baseline},
                   {"note", r.note}, {"failed", r.failed}});
    }
    fmt::print("{}\n", nlohmann::json{{"version", kVersion}, {"commit", kCommit}, {"rows", j}}.dump(2));
  }
  std::size_t failed = 0;
  for (const auto& r : rows) failed += r.failed;
  if (failed) {
    std::fprintf(stderr, "axonguide: cannot run: bench %s --backend %s: %zu of %zu measurements failed (no figure is "
                 "reported for them)\n", args.what.c_str(), args.backend.c_str(), failed, rows.size());
    return kExitCannotRun;
  }
  return kExitOk;
}

}  // namespace axg::app
