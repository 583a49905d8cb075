// Appositions (issue 42; SPEC §3.9; docs/methods.md §2.13): the closest points of two
// segments, the spatial hash against the brute-force search, runs of contacts, the
// realisation options, the scene's checks and the run's outputs.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "axonguide/core/segment.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/network/appositions.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/support/error.hpp"
#include "support.hpp"

namespace axg {
namespace {

using core::Vec3;
using network::Contact;
using network::Segments;

// ---- the closest points of two segments ------------------------------------------------

rc::Gen<Vec3> gen_point() {
  return rc::gen::exec([] {
    return Vec3{*rc::gen::inRange(-40, 41) / 8.0, *rc::gen::inRange(-40, 41) / 8.0, *rc::gen::inRange(-40, 41) / 8.0};
  });
}

RC_GTEST_PROP(segments, ClosestPointsAreNoFartherThanAnyPairOnTheSegments, ()) {
  // Grid-valued points make zero-length, parallel and collinear segments common.
  const Vec3 p0 = *gen_point(), q0 = *gen_point();
  const Vec3 p1 = *rc::gen::oneOf(gen_point(), rc::gen::just(p0));
  const Vec3 q1 = *rc::gen::oneOf(gen_point(), rc::gen::just(q0), rc::gen::just(q0 + (p1 - p0)),
                                  rc::gen::just(q0 - 0.5 * (p1 - p0)));
  const core::SegmentPair c = core::closest_points(p0, p1, q0, q1);
  RC_ASSERT(c.s >= 0.0 && c.s <= 1.0 && c.t >= 0.0 && c.t <= 1.0);
  RC_ASSERT(c.dist2 == core::norm2((p0 + c.s * (p1 - p0)) - (q0 + c.t * (q1 - q0))));
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double other = core::norm2((p0 + (i / 20.0) * (p1 - p0)) - (q0 + (j / 20.0) * (q1 - q0)));
      RC_ASSERT(c.dist2 <= other + 1e-9);
    }
}

TEST(segments, ParallelSegmentsMeetAtTheSmallestAxonParameter) {
  // Overlap over x in [2, 4]: the closest points are taken where the overlap starts.
  const core::SegmentPair c = core::closest_points({0, 0, 0}, {4, 0, 0}, {2, 1, 0}, {6, 1, 0});
  EXPECT_DOUBLE_EQ(c.s, 0.5);
  EXPECT_DOUBLE_EQ(c.t, 0.0);
  EXPECT_DOUBLE_EQ(c.dist2, 1.0);
  // Reversed dendrite: the same point of the axon.
  const core::SegmentPair r = core::closest_points({0, 0, 0}, {4, 0, 0}, {6, 1, 0}, {2, 1, 0});
  EXPECT_DOUBLE_EQ(r.s, 0.5);
  EXPECT_DOUBLE_EQ(r.t, 1.0);
  // Two zero-length segments, and one zero-length axon segment.
  EXPECT_DOUBLE_EQ(core::closest_points({1, 1, 1}, {1, 1, 1}, {1, 1, 3}, {1, 1, 3}).dist2, 4.0);
  const core::SegmentPair z = core::closest_points({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, {4, 0, 0});
  EXPECT_DOUBLE_EQ(z.t, 0.25);
  EXPECT_DOUBLE_EQ(z.dist2, 2.0);
}

// ---- hand-built neurites ---------------------------------------------------------------

using network::Polyline;

Segments build(const std::vector<std::vector<Polyline>>& neurons, const std::vector<Vec3>& soma, double radius) {
  return network::segments_from_polylines(neurons, soma, radius);
}

// A straight neurite from a to b cut into k segments (after its stem start at a).
Polyline straight(std::uint8_t type, Vec3 a, Vec3 b, int k) {
  Polyline l{type, {}};
  for (int i = 0; i <= k; ++i) l.points.push_back(a + (static_cast<double>(i) / k) * (b - a));
  return l;
}

SynapseParams all_realised() {
  SynapseParams p;
  p.distance = 1.0;
  return p;
}

network::Appositions appositions(const Segments& g, double d, const SynapseParams& p = all_realised()) {
  return network::group_appositions(g, network::find_contacts(g, d, p.autapses), p);
}

TEST(appositions, ACrossingIsOneAppositionAtEveryStep) {
  // Neuron 0's axon along x, neuron 1's dendrite along y, 0.5 above it; somas far away.
  for (const int k : {1, 2, 4, 8, 16, 64}) {
    const Segments g = build({{straight(2, {-10, 0, 0}, {10, 0, 0}, k)}, {straight(3, {0, -10, 0.5}, {0, 10, 0.5}, k)}},
                             {{-50, 0, 0}, {50, 0, 0}}, 1.0);
    const network::Appositions a = appositions(g, 1.0);
    ASSERT_EQ(a.size(), 1u) << k << " segments";
    EXPECT_EQ(a.at[0].pre, 0u);
    EXPECT_EQ(a.at[0].post, 1u);
    EXPECT_DOUBLE_EQ(a.at[0].distance, 0.5);
    EXPECT_DOUBLE_EQ(a.on_dendrite[0].z, 0.5);
    EXPECT_GE(a.contacts[0], 1u);
  }
}

TEST(appositions, AParallelRunIsOneApposition) {
  for (const int k : {1, 4, 32}) {
    const Segments g = build({{straight(2, {0, 0, 0}, {10, 0, 0}, k)}, {straight(3, {0, 0.5, 0}, {10, 0.5, 0}, k)}},
                             {{-50, 0, 0}, {50, 0, 0}}, 1.0);
    const network::Appositions a = appositions(g, 1.0);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_GE(a.contacts[0], static_cast<std::uint32_t>(k));
  }
}

TEST(appositions, TwoSeparateCrossingsOfOnePairAreTwo) {
  // The axon crosses the dendrite's two branches 6 apart.
  Polyline trunk = straight(3, {0, -10, 0}, {0, 0, 0}, 4);
  const Polyline left{3, {{-3, 4, 0}, {-3, 10, 0}}, 6}, right{3, {{3, 4, 0}, {3, 10, 0}}, 6};
  const Segments g = build({{straight(2, {-10, 7, 0.2}, {10, 7, 0.2}, 40)}, {trunk, left, right}},
                           {{-50, 0, 0}, {50, 0, 0}}, 1.0);
  const network::Appositions a = appositions(g, 1.0);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_DOUBLE_EQ(a.on_dendrite[0].x, -3.0);
  EXPECT_DOUBLE_EQ(a.on_dendrite[1].x, 3.0);
  EXPECT_EQ(network::connections_of(a).size(), 1u);
  EXPECT_EQ(network::connections_of(a)[0].synapses, 2u);
}

TEST(appositions, ASomaCountsFromItsSurfaceAndItsOwnNeverDoes) {
  // Neuron 0's axon passes 2.5 from neuron 1's soma centre (radius 2): 0.5 from its surface.
  const Segments g = build({{straight(2, {1, 0, 0}, {10, 0, 0}, 9)}, {}}, {{0, 0, 0}, {5, 2.5, 0}}, 2.0);
  SynapseParams p = all_realised();
  p.autapses = true;  // the axon starts on its own soma: never a contact
  const network::Appositions a = appositions(g, 1.0, p);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a.at[0].post, 1u);
  EXPECT_EQ(a.at[0].post_sample, network::kSomaSample);
  EXPECT_DOUBLE_EQ(a.at[0].distance, 0.5);
  EXPECT_DOUBLE_EQ(a.on_dendrite[0].y, 0.5);
  EXPECT_TRUE(appositions(g, 0.4, p).at.empty());
}

TEST(appositions, TheCapKeepsTheLowestSamplesAndTheProbabilityIsADrawEach) {
  // The axon crosses five dendrites of neuron 1, each a separate stem.
  std::vector<Polyline> dendrites;
  for (int k = 0; k < 5; ++k) dendrites.push_back(straight(3, {4.0 * k, -5, 0}, {4.0 * k, 5, 0}, 5));
  const Segments g = build({{straight(2, {-2, 0, 0.1}, {20, 0, 0.1}, 22)}, dendrites}, {{-50, 0, 0}, {50, 0, 0}}, 1.0);
  SynapseParams p = all_realised();
  EXPECT_EQ(network::connections_of(appositions(g, 1.0, p))[0].synapses, 5u);
  p.cap = 2;
  const network::Appositions capped = appositions(g, 1.0, p);
  EXPECT_EQ(std::vector<std::uint8_t>(capped.realised.begin(), capped.realised.end()),
            (std::vector<std::uint8_t>{1, 1, 0, 0, 0}));
  p.cap = 0;
  EXPECT_TRUE(network::connections_of(appositions(g, 1.0, p)).empty());
  p.cap = 0xffffffffu;
  p.probability = 0.0;
  EXPECT_TRUE(network::connections_of(appositions(g, 1.0, p)).empty());
  // p = 0.5 over many seeds: each apposition realised about half the time, independently.
  p.probability = 0.5;
  int realised = 0;
  for (std::uint64_t seed = 0; seed < 400; ++seed) {
    p.seed = seed;
    for (const std::uint8_t x : appositions(g, 1.0, p).realised) realised += x;
  }
  EXPECT_NEAR(realised / 2000.0, 0.5, 4.0 * std::sqrt(0.25 / 2000.0));
}

// Random trees: a few neurons, each a few neurites of random walks that branch from earlier
// samples, with zero-length steps, on a small grid so that parallel and touching segments
// are common.
rc::Gen<std::vector<std::vector<Polyline>>> gen_neurons(int count) {
  return rc::gen::exec([count] {
    std::vector<std::vector<Polyline>> out(static_cast<std::size_t>(count));
    for (auto& lines : out) {
      const int neurites = *rc::gen::inRange(0, 6);
      std::uint32_t samples = 0;
      for (int n = 0; n < neurites; ++n) {
        Polyline l{static_cast<std::uint8_t>(*rc::gen::element(2, 3)), {}};
        l.from = samples > 0 && *rc::gen::arbitrary<bool>() ? *rc::gen::inRange<std::uint32_t>(2, samples + 2) : 1u;
        Vec3 p{*rc::gen::inRange(-16, 17) / 8.0, *rc::gen::inRange(-16, 17) / 8.0, *rc::gen::inRange(-8, 9) / 8.0};
        const int len = *rc::gen::inRange(1, 12);
        for (int k = 0; k < len; ++k) {
          l.points.push_back(p);
          p = p + Vec3{*rc::gen::inRange(-4, 5) / 4.0, *rc::gen::inRange(-4, 5) / 4.0, *rc::gen::inRange(-2, 3) / 4.0};
        }
        l.step = *rc::gen::inRange<std::uint32_t>(0, 20);
        samples += static_cast<std::uint32_t>(l.points.size());
        lines.push_back(l);
      }
    }
    return out;
  });
}

RC_GTEST_PROP(appositions, TheHashFindsExactlyTheBruteForceContacts, ()) {
  const int count = *rc::gen::inRange(1, 7);
  const auto neurons = *gen_neurons(count);
  std::vector<Vec3> soma;
  for (int i = 0; i < count; ++i) soma.push_back(*gen_point());
  const Segments g = build(neurons, soma, *rc::gen::element(0.25, 1.0));
  const double d = *rc::gen::element(0.01, 0.25, 0.5, 1.0, 3.0);
  const bool autapses = *rc::gen::arbitrary<bool>();
  const std::vector<Contact> fast = network::find_contacts(g, d, autapses);
  const std::vector<Contact> brute = network::find_contacts_brute(g, d, autapses);
  RC_ASSERT(fast == brute);
  RC_TAG(fast.empty() ? "none" : "some");
  // Every contact within d, none of a neuron with itself unless asked, never its own soma.
  for (const Contact& c : fast) {
    RC_ASSERT(c.distance <= d);
    RC_ASSERT(autapses || c.pre != c.post);
    RC_ASSERT(!(c.pre == c.post && c.post_sample == network::kSomaSample));
  }
  // Runs partition the contacts, and the run's chunked path gives the same appositions.
  const network::Appositions a = network::group_appositions(g, fast, all_realised());
  std::uint64_t counted = 0;
  const network::Appositions b = network::find_appositions(g, [&] {
    SynapseParams p = all_realised();
    p.distance = d;
    p.autapses = autapses;
    return p;
  }(), &counted);
  RC_ASSERT(counted == fast.size());
  RC_ASSERT(b.at == a.at && b.contacts == a.contacts && b.realised == a.realised && b.on_dendrite.size() == a.size());
  std::uint64_t gathered = 0;
  for (const std::uint32_t n : a.contacts) gathered += n;
  RC_ASSERT(gathered == fast.size());
}

// ---- the scene and the run -------------------------------------------------------------

nlohmann::json culture_json() {
  std::ifstream in(test::source_dir() + "/scenes/culture.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["neurons"]["count"] = 60;
  j["neurons"]["region"]["radius"] = 300;
  j["steps"] = 60;
  j["dt"] = 1.0;
  j["synapses"] = {{"distance", 3.0}};
  return j;
}

void expect_refused(nlohmann::json j, const std::string& key, const std::string& words) {
  try {
    parse_scene(j.dump(), "test");
    ADD_FAILURE() << "accepted " << j.dump();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(synapse_scene, BadValuesNameTheKeyTheValueAndTheRange) {
  nlohmann::json j = culture_json();
  j["synapses"]["distance"] = 0;
  expect_refused(j, "synapses.distance = 0", "> 0");
  j["synapses"]["distance"] = 500;  // bounds radius 300: above 600 / 16
  expect_refused(j, "synapses.distance = 500", "the range the detection's spatial hash supports");
  j["synapses"]["distance"] = 1e-5;
  expect_refused(j, "synapses.distance = 1e-05", "[");
  j = culture_json();
  j["synapses"]["probability"] = 1.5;
  expect_refused(j, "synapses.probability = 1.5", "[0, 1]");
  j = culture_json();
  j["synapses"]["max_per_connection"] = -1;
  expect_refused(j, "synapses.max_per_connection = -1", "");
  j = culture_json();
  j.erase("arbours");
  expect_refused(j, "synapses", "arbour scene");
}

TEST(synapse_scene, TheRunWritesAppositionsConnectionsAndWeights) {
  const Scene s = parse_scene(culture_json().dump(), "test").scene;
  RunOptions o;
  const RunResult r = run_scene(s, o);
  ASSERT_GT(r.synapses.size(), 0u) << "the test culture grew no apposition";
  test::TempDir out;
  write_outputs(r, out.path(), "test", 2, {});
  std::ifstream syn(out.path() / "synapses.csv"), con(out.path() / "connections.csv");
  std::string header;
  std::getline(syn, header);
  EXPECT_EQ(header, "pre,post,pre_sample,post_sample,x,y,z,distance,contacts,step,realised");
  std::getline(con, header);
  EXPECT_EQ(header, "source,target,synapses,first_step");
  std::size_t rows = 0, synapses = 0;
  for (std::string line; std::getline(con, line);) {
    ++rows;
    synapses += std::stoul(line.substr(line.find(',', line.find(',') + 1) + 1));
  }
  EXPECT_EQ(rows, r.synapse_connections.size());
  EXPECT_EQ(synapses, r.synapses.size());  // probability 1, no cap: every apposition
  // The graph's edges are the connections.
  EXPECT_EQ(r.graph.out.edges(), r.synapse_connections.size());
  // Synapse positions are on the post neuron's dendrites (or soma surface), within d of the axon.
  const network::Segments g = network::segments_of(r.arbours, r.soma, s.neurons.soma_radius);
  EXPECT_TRUE(network::find_contacts(g, 3.0, false) == network::find_contacts_brute(g, 3.0, false));
}

TEST(synapse_scene, ThreadCountNeverChangesAByte) {
  const Scene s = parse_scene(culture_json().dump(), "test").scene;
  const auto one = test::run_hashes(s, 1);
  ASSERT_TRUE(one.count("synapses.csv"));
  EXPECT_EQ(test::run_hashes(s, 2), one);
  EXPECT_EQ(test::run_hashes(s, 5), one);
}

}  // namespace
}  // namespace axg
