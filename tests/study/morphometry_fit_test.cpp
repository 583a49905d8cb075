// The morphometric fit (study/morphometry_fit.hpp; docs/methods.md §12.8): it recovers a
// parameter from data its own model made (other seeds), and refuses malformed data.
#include <gtest/gtest.h>

#include <fstream>

#include "axonguide/study/morphometry_fit.hpp"
#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

Scene small_culture() {
  Scene s = load_scene_file(test::source_dir() + "/scenes/culture.json").scene;
  s.neurons.count = 80;
  s.neurons.radius = 520.0;
  return s;
}

// Data made by the model at v0 = 2.6 um/h (seeds 11-12, se from those neurons); a fit of
// axon.v0 alone from 1.3 um/h on seeds 1-2 lands within 10 % of 2.6, with chi2/dof near 1.
TEST(morphometry_fit, RecoversTheElongationRateFromItsOwnModel) {
  Scene truth = small_culture();
  truth.arbours->axon.v0 = 2.6;
  std::vector<morphofit::DataRow> data;
  for (const double age : {1.0, 3.0})
    for (const morphofit::ModelRow& m : morphofit::model_at(truth, age, {11, 12}))
      if (m.statistic == "total_axon_length" || m.statistic == "axons_mean_terminal_segment_length")
        data.push_back({m.statistic, age, m.n, m.mean, 0.0, m.se});
  Scene start = small_culture();
  start.arbours->axon.v0 = 1.3;
  morphofit::Options o;
  o.parameters = {{"axon.v0", 0, 0}};
  o.seeds = {1, 2};
  o.predict_days = {};
  const morphofit::Result r = morphofit::fit(start, data, o);
  ASSERT_EQ(r.parameters.size(), 1u);
  EXPECT_NEAR(r.parameters[0].best, 2.6, 0.26);
  EXPECT_LT(r.parameters[0].lo, r.parameters[0].best);
  EXPECT_GT(r.parameters[0].hi, r.parameters[0].best);
  EXPECT_EQ(r.dof, 3);
  EXPECT_LT(r.chi2, 4.0 * r.dof + 10.0);
  EXPECT_NEAR(morphofit::get_parameter(r.best, "axon.v0"), r.parameters[0].best, 1e-12);
}

TEST(morphometry_fit, RefusesMalformedDataAndUnknownParameters) {
  test::TempDir dir;
  auto write = [&](const std::string& text) {
    const fs::path p = dir.path() / "data.csv";
    std::ofstream(p) << text;
    return p.string();
  };
  const std::string header = "# comment\nstatistic,age_days,n,mean,sd,se,ci95_lo\n";
  EXPECT_TRUE(morphofit::is_morphometric_data(write(header)));
  EXPECT_THROW(morphofit::load_data(write(header)), InputError);  // no rows
  EXPECT_THROW(morphofit::load_data(write(header + "axon_girth,1,4,1,1,1,0\n")), InputError);
  EXPECT_THROW(morphofit::load_data(write(header + "total_axon_length,1,4,x,1,1,0\n")), InputError);
  EXPECT_THROW(morphofit::load_data(write(header + "total_axon_length,1,4,1,1,0,0\n")), InputError);
  try {
    morphofit::load_data(write(header + "total_axon_length,1,4,1,1,1,0\nterminal_segments_per_axon,2\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(morphofit::is_morphometric_data(write("line,concentration,steepness\n")));
  const Scene s = small_culture();
  EXPECT_THROW(morphofit::get_parameter(s, "axon.girth"), InputError);
  EXPECT_EQ(morphofit::get_parameter(s, "axon.v0"), s.arbours->axon.v0);
  EXPECT_THROW(morphofit::get_parameter(Scene{}, "axon.v0"), InputError);  // no arbours
}

}  // namespace
}  // namespace axg
