#include "axonguide/distributed/decomposed_run.hpp"

#include "axonguide/distributed/placement.hpp"
#include "axonguide/support/error.hpp"

namespace axg::distributed {

using nlohmann::json;

namespace {

const Scene& refuse_arbours(const Scene& scene) {
  if (scene.arbours)
    throw RunError("mpirun: arbour scenes over ranks are designed (docs/scaling.md §2.6a: growth cones migrate between "
                   "blocks as axons do now) but not built; run the scene without mpirun");
  return scene;
}

}  // namespace

DecomposedRun::DecomposedRun(const Scene& scene, Comm& comm)
    : comm_(comm), d_(decompose(refuse_arbours(scene), comm.size())) {}

void DecomposedRun::attach(RunOptions& options) {
  options.place = [this](const Scene& scene) {
    const Traffic before = comm_.traffic();
    DecomposedPlacement p = place_decomposed(scene, d_, comm_);
    report_.placement = comm_.traffic() - before;
    report_.placing = p.stats;
    placed_ = std::move(p.somas);
    Placement out;
    out.soma = std::move(p.all);
    out.redraws = p.redraws;
    return out;
  };
  // A fresh run builds its engine from the decomposed placement; a resumed one from the
  // checkpoint's somas, which every rank read.
  options.make_engine = [this](const Scene& scene, const Placement& placement) {
    RankSomas somas = placed_ ? std::move(*placed_) : rank_somas(placement.soma, d_, comm_.rank());
    placed_.reset();
    return make_decomposed_engine(scene, d_, comm_, std::move(somas), report_);
  };
  // Between two steps: part of a step's traffic.
  options.agree = [this](unsigned flags) {
    const Traffic before = comm_.traffic();
    std::vector<std::uint64_t> v{flags};
    comm_.allreduce(v, Reduce::kOr);
    const Traffic spent = comm_.traffic() - before;
    report_.steps.collectives += spent.collectives;
    report_.steps.collective_bytes += spent.collective_bytes;
    return static_cast<unsigned>(v[0]);
  };
}

json DecomposedRun::facts() {
  const RankReport& r = report_;
  std::vector<std::uint64_t> sum{r.owned_somas,          r.halo_somas,          r.migrated,
                                 r.placement.collective_bytes, r.steps.messages,  r.steps.message_bytes,
                                 r.steps.collective_bytes,     r.gathers.messages, r.gathers.message_bytes,
                                 r.field.migrated,             r.field.halo_particles, r.field.owned_particles,
                                 r.field.halo.messages,        r.field.halo.message_bytes, r.field.ghost_values,
                                 r.field.far_migrated};
  auto micro = [](double s) { return static_cast<std::uint64_t>(s * 1e6); };
  // Peak memory so far: rank 0's (which holds the whole result) and the largest other's.
  const std::uint64_t peak = peak_rss_bytes();
  std::vector<std::uint64_t> most{r.owned_somas, ~r.owned_somas, r.steps.message_bytes, r.steps.collectives,
                                  comm_.root() ? peak : 0, comm_.root() ? 0 : peak,
                                  micro(r.placing.window_seconds), micro(r.placing.gather_seconds),
                                  micro(r.placing.replicated_seconds), r.field.pipeline_stages};
  comm_.allreduce(sum, Reduce::kSum);
  comm_.allreduce(most, Reduce::kMax);
  const double steps = static_cast<double>(std::max<std::uint64_t>(r.steps_run, 1));
  auto per_step = [&](std::uint64_t v) { return static_cast<double>(v) / steps; };
  return {{"ranks", d_.ranks},
          {"blocks", d_.blocks},
          {"block_edge_lu", d_.edge},
          {"halo_lu", d_.halo},
          {"somas_per_rank", {{"min", ~most[1]}, {"max", most[0]}}},
          {"halo_somas", sum[1]},
          {"placement", {{"rounds", r.placing.rounds},
                         {"scan_passes", r.placing.scan_passes},
                         {"extra_searches", r.placing.extra_searches},
                         {"collective_bytes", sum[3]},
                         {"seconds_max_rank", {{"windows", most[6] * 1e-6},
                                               {"all_gathers", most[7] * 1e-6},
                                               {"replicated", most[8] * 1e-6}}}}},
          {"steps", r.steps_run},
          {"per_step",
           {{"migrated_axons", per_step(sum[2])},
            {"messages", per_step(sum[4])},
            {"message_bytes", per_step(sum[5])},
            {"collectives_per_rank", per_step(most[3])},
            {"collective_bytes", per_step(sum[6])},
            {"max_rank_message_bytes", per_step(most[2])},
            {"migrated_particles", per_step(sum[9])},
            {"far_particles", per_step(sum[15])},
            {"halo_particles", per_step(sum[10])},
            {"owned_particles", per_step(sum[11])},
            {"halo_messages", per_step(sum[12])},
            {"halo_message_bytes", per_step(sum[13])},
            {"ghost_values", per_step(sum[14])},
            {"pipeline_stages", per_step(most[9])}}},
          {"gathered", {{"messages", sum[7]}, {"bytes", sum[8]}}},
          {"peak_memory_bytes", {{"rank0", most[4]}, {"largest_other", most[5]}}}};
}

}  // namespace axg::distributed
