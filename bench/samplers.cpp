// Uniform directions on S^2: ours (each point a pure function of its index) against
// GSL's gsl_ran_dir_3d and Boost's uniform_on_sphere (sequential engines), in one run.
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_on_sphere.hpp>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/placement/sampler_nd.hpp"
#include "axonguide/support/threads.hpp"
#include "bench.hpp"

namespace axg::bench {

namespace {

volatile double g_sink;

void consume(const std::vector<core::Vec3>& v) {
  double s = 0;
  for (std::size_t i = 0; i < v.size(); i += 97) s += v[i].x;
  g_sink = s;
}

}  // namespace

std::vector<Row> samplers(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int max_threads = o.max_threads > 0 ? o.max_threads : static_cast<int>(tbb::info::default_concurrency());
  const std::size_t n = o.quick ? 200000 : 2000000;
  std::vector<core::Vec3> out(n);

  // Boost's uniform_on_sphere is the baseline every row is paired with.
  boost::random::mt19937 boost_gen(12345);
  boost::random::uniform_on_sphere<double> boost_dist(3);
  auto boost_run = [&](std::size_t m) {
    for (std::size_t i = 0; i < m; ++i) {
      const std::vector<double> v = boost_dist(boost_gen);
      out[i] = {v[0], v[1], v[2]};
    }
    consume(out);
  };
  {
    const double t = time_median([&] { boost_run(n); }, 9);
    emit({"samplers", "direction S^2", "boost uniform_on_sphere (mt19937)", 1, double(n), t, n / t, "points/s", 1.0,
          "boost", ""});
  }
  {
    gsl_rng* r = gsl_rng_alloc(gsl_rng_mt19937);
    const Paired p = time_paired([&] { boost_run(n); },
                                 [&] {
                                   for (std::size_t i = 0; i < n; ++i) gsl_ran_dir_3d(r, &out[i].x, &out[i].y, &out[i].z);
                                   consume(out);
                                 });
    gsl_rng_free(r);
    emit({"samplers", "direction S^2", "gsl_ran_dir_3d (mt19937)", 1, double(n), p.our_seconds, n / p.our_seconds,
          "points/s", p.speedup, "boost", "paired rounds, median ratio"});
  }

  const std::pair<core::Sampler, const char*> ours[] = {{core::Sampler::kRejection, "rejection"},
                                                         {core::Sampler::kNormal, "normal"},
                                                         {core::Sampler::kTrig, "trig"},
                                                         {core::Sampler::kCoordinate, "coordinate"}};
  for (auto [sampler, name] : ours) {
    const std::size_t m = sampler == core::Sampler::kCoordinate ? n / 20 : n;
    std::vector<int> thread_counts{1};
    if (max_threads > 1) thread_counts.push_back(max_threads);
    for (int threads : thread_counts) {
      const Paired p = with_threads(threads, [&] {
        return time_paired([&] { boost_run(m); },
                           [&] {
                             tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 4096),
                                               [&](const tbb::blocked_range<std::size_t>& r) {
                                                 for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                                   core::Rng rng(1, core::Stream::kBenchmark, i, 0);
                                                   // The core samplers inline; the coordinate one calls GSL.
                                                   out[i] = sampler == core::Sampler::kCoordinate
                                                                ? sample_direction3(sampler, rng)
                                                                : core::direction3(sampler, rng);
                                                 }
                                               });
                             consume(out);
                           },
                           sampler == core::Sampler::kCoordinate ? 3 : 9);
      });
      emit({"samplers", "direction S^2", std::string("axonguide ") + name, threads, double(m), p.our_seconds,
            m / p.our_seconds, "points/s", p.speedup, "boost (1 thread)", "paired rounds, median ratio"});
    }
  }

  // The report's Table 3: placing N neurons (overlap rejection included), per sampler.
  const double table3[4][4] = {{0.25, 0.13, 0.12, 0.12}, {0.40, 0.25, 0.24, 0.24},
                               {0.41, 0.39, 0.39, 0.40}, {0.70, 0.69, 0.68, 0.70}};
  const std::uint64_t sizes[4] = {500, 2500, 5000, 10000};
  for (int k = 0; k < 4; ++k)
    for (int s = 0; s < 4; ++s) {
      Scene scene = paper_direct_scene(sizes[k]);
      scene.neurons.sampler = ours[s].first;
      const double t = with_threads(max_threads, [&] { return time_median([&] { place_neurons(scene); }); });
      emit({"placement", "place neurons (Table 3)", std::string("axonguide ") + ours[s].second, max_threads,
            double(sizes[k]), t, double(sizes[k]) / t, "neurons/s", table3[k][s] / t, "report Table 3",
            "ratio = report time / our time"});
    }
  return rows;
}

}  // namespace axg::bench
