#include <fmt/format.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/golden.hpp"
#include "axonguide/validate/validate.hpp"
#include "backend.hpp"
#include "commands.hpp"

namespace axg::app {

int cmd_validate(const ValidateArgs& a) {
  validate::Options o;
  o.quick = a.quick;
  o.threads = a.threads;
  o.points_file = a.points;
  o.radius = a.radius;
  o.allow_skip = a.allow_skip;
  if (!a.points.empty() && a.what != "samplers")
    throw InputError("--points: only `validate samplers` takes a point file");
  return validate::run_validation(a.what, a.report, o);
}

int cmd_golden(const GoldenArgs& a) {
  const std::filesystem::path dir = a.dir.empty() ? validate::default_golden_dir() : std::filesystem::path(a.dir);
  if (a.action == "check") require_backend(a.backend);  // before any network is run
  const int threads = resolve_threads(a.threads);
  if (a.action == "bless") {
    const auto changed = validate::golden_bless(dir, a.reason, threads, a.only);
    fmt::print("golden bless: {} network(s) changed{}; reason recorded in {}\n", changed.size(),
               changed.empty() ? "" : fmt::format(" ({})", fmt::join(changed, ", ")), (dir / "CHANGELOG.md").string());
    return kExitOk;
  }
  const auto results = validate::golden_check(dir, engine_factory(a.backend), threads);
  int failed = 0;
  for (const auto& r : results) {
    fmt::print("{:<45} {}\n", r.name, r.pass ? "identical" : r.verified ? "DIFFERS" : "REFUSED (does not verify)");
    for (const auto& d : r.differences) fmt::print("    {}\n", d);
    failed += !r.pass;
  }
  fmt::print("golden check ({} backend): {} of {} networks identical\n", a.backend, results.size() - failed,
             results.size());
  return failed ? kExitCheckFailed : kExitOk;
}

}  // namespace axg::app
