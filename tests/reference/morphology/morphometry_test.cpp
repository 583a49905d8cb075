// Morphometry (morphology/morphometry.hpp): the data's segment conventions on a tree worked
// by hand, the counting identities on random trees, and every malformed SWC refused with
// its file and line.
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "axonguide/morphology/morphometry.hpp"
#include "axonguide/support/error.hpp"

namespace axg::morphology {
namespace {

// A soma; an axon 10 um from the soma's centre that runs 10 um and forks into two 14.14 um
// branches; a dendrite that runs 10 um and forks into two 5 um branches; an unbranched 20 um
// dendrite.
const char* kHand =
    "# by hand\n"
    "1 1 0 0 0 5 -1\n"
    "2 2 10 0 0 0.5 1\n"
    "3 2 20 0 0 0.5 2\n"
    "4 2 30 10 0 0.5 3\n"
    "5 2 30 -10 0 0.5 3\n"
    "6 3 -10 0 0 1 1\n"
    "7 3 -20 0 0 1 6\n"
    "8 3 -20 5 0 1 7\n"
    "9 3 -20 -5 0 1 7\n"
    "10 4 0 -10 5 1 1\n"
    "11 4 0 -30 5 1 10\n";

TEST(morphometry, TheDataConventionsOnATreeWorkedByHand) {
  const Morphology m = parse_swc(kHand, "hand.swc");
  const NeuronStats s = measure(m, Projection::kNone);
  ASSERT_TRUE(s.has_axon);
  EXPECT_DOUBLE_EQ(s.axon.total_length, 10 + 2 * std::sqrt(200.0));  // the soma-to-stem piece is not neurite
  EXPECT_EQ(s.axon.branch_points, 1);
  EXPECT_EQ(s.axon.terminal_segments, 2);
  EXPECT_DOUBLE_EQ(s.axon.mean_terminal_segment_length, std::sqrt(200.0));
  EXPECT_DOUBLE_EQ(s.axon.mean_intermediate_segment_length, 10.0);
  ASSERT_EQ(s.dendrites.size(), 2u);
  EXPECT_DOUBLE_EQ(s.dendrites[0].total_length, 20.0);
  EXPECT_EQ(s.dendrites[0].branch_points, 1);
  EXPECT_DOUBLE_EQ(s.dendrites[0].mean_terminal_segment_length, 5.0);
  // An unbranched neurite's mean intermediate segment length enters as 0, as in the data.
  EXPECT_EQ(s.dendrites[1].branch_points, 0);
  EXPECT_EQ(s.dendrites[1].terminal_segments, 1);
  EXPECT_DOUBLE_EQ(s.dendrites[1].mean_intermediate_segment_length, 0.0);
  EXPECT_DOUBLE_EQ(s.dendrites[1].total_length, 20.0);
  const auto rows = population({s});
  ASSERT_EQ(rows.size(), 11u);
  EXPECT_EQ(rows[5].statistic, "number_of_dendrites_per_neuron");
  EXPECT_EQ(rows[5].mean, 2.0);
  EXPECT_EQ(rows[6].n, 2u);
  EXPECT_DOUBLE_EQ(rows[6].mean, 20.0);
  EXPECT_DOUBLE_EQ(rows[7].sd, std::sqrt(0.5));
  EXPECT_TRUE(std::isnan(rows[0].sd));  // one axon: no sd
  // Sholl, axon: 1 crossing at 10 um, 2 at 20 and 30, none at 40 (an end on the circle is inside).
  EXPECT_EQ(sholl(m, 2, 10, Projection::kNone), (std::vector<int>{1, 2, 2, 0}));
  // In projection the apical dendrite's z no longer counts (it has none across its length anyway).
  EXPECT_DOUBLE_EQ(measure(m, Projection::kXY).dendrites[1].total_length, 20.0);
}

// A random tree: stems of types 2, 3, 4 from one soma, each sample with 0 to 3 children.
std::string random_tree(int& stems, int& excess, double& length) {
  std::string text = "1 1 0 0 0 5 -1\n";
  std::int64_t next = 2;
  stems = excess = 0;
  length = 0;
  struct Open {
    std::int64_t id;
    int type;
    double x, y, z;
    int depth;
  };
  std::vector<Open> open;
  const int nstems = *rc::gen::inRange(1, 5);
  for (int k = 0; k < nstems; ++k) {
    const int type = *rc::gen::element(2, 3, 4);
    const double x = *rc::gen::inRange(-50, 50), y = *rc::gen::inRange(-50, 50), z = *rc::gen::inRange(-5, 5);
    text += fmt::format("{} {} {} {} {} 1 1\n", next, type, x, y, z);
    open.push_back({next++, type, x, y, z, 0});
    ++stems;
  }
  while (!open.empty()) {
    const Open o = open.back();
    open.pop_back();
    const int kids = o.depth > 6 ? 0 : *rc::gen::inRange(0, 4);
    if (kids > 2) excess += kids - 2;
    for (int c = 0; c < kids; ++c) {
      const double x = o.x + *rc::gen::inRange(-20, 21), y = o.y + *rc::gen::inRange(-20, 21), z = o.z;
      length += std::sqrt((x - o.x) * (x - o.x) + (y - o.y) * (y - o.y));
      text += fmt::format("{} {} {} {} {} 1 {}\n", next, o.type, x, y, z, o.id);
      open.push_back({next++, o.type, x, y, z, o.depth + 1});
    }
  }
  return text;
}

// For any tree: terminal segments - branch points = stems + the extra children of branch
// points of degree > 2, summed over the axon and every dendrite; the lengths add up.
RC_GTEST_PROP(morphometry, SegmentsCountTheTreesNodes, ()) {
  int stems = 0, excess = 0;
  double length = 0;
  const std::string text = random_tree(stems, excess, length);
  const NeuronStats s = measure(parse_swc(text, "random.swc"), Projection::kNone);
  int terminals = s.axon.terminal_segments, branches = s.axon.branch_points;
  double total = s.axon.total_length;
  for (const auto& d : s.dendrites) terminals += d.terminal_segments, branches += d.branch_points, total += d.total_length;
  RC_ASSERT(terminals - branches == stems + excess);
  RC_ASSERT(std::fabs(total - length) <= 1e-9 * (1 + length));
  // Each neurite's mean terminal length times its count is at most its total length.
  for (const auto& d : s.dendrites)
    RC_ASSERT(d.mean_terminal_segment_length * d.terminal_segments <= d.total_length * (1 + 1e-12) + 1e-12);
}

TEST(morphometry, MalformedSwcIsRefusedNamingTheFileAndTheLine) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"1 1 0 0 0 1 -1\n2 2 1 0 0 1 7\n", "bad.swc:2: sample 2: its parent 7 is not in the file"},
      {"1 1 0 0 0 1 -1\n2 2 1 0 0 1 3\n3 2 2 0 0 1 2\n", "bad.swc:2: sample 2: its parents lead back to it (a cycle)"},
      {"1 1 0 0 0 1 -1\n2 2 1 0 0 1 2\n", "bad.swc:2: sample 2: its parents lead back to it (a cycle)"},
      {"1 1 0 0 0 1 -1\n# c\n2 2 1 0 0 1 3\n3 2 2 0 0 1 1\n",
       "bad.swc:3: sample 2: its parent 3 comes after it (line 4)"},
      {"1 1 0 0 0 1 -1\n2 2 1 0 x 1 1\n", "bad.swc:2: field 5 (z) = \"x\" is not a finite number"},
      {"1 1 0 0 0 1 -1\n2 2.5 1 0 0 1 1\n", "bad.swc:2: field 2 (type) = \"2.5\" is not a whole number"},
      {"1 1 0 0 0 1 -1\n2 2 1 0 0 nan 1\n", "bad.swc:2: field 6 (radius) = \"nan\" is not a finite number"},
      {"1 1 0 0 0 1 -1\n2 2 1 0 0 1\n", "bad.swc:2: 6 fields"},
      {"1 1 0 0 0 1 -1\n1 2 1 0 0 1 1\n", "bad.swc:2: id 1 is given twice (first on line 1)"},
      {"1 1 0 0 0 1 -2\n", "bad.swc:1: parent -2"},
      {"# nothing\n", "bad.swc:1: no samples"},
  };
  for (const auto& [text, needle] : cases) {
    try {
      parse_swc(text, "bad.swc");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what() << "\nwanted: " << needle;
    }
  }
}

}  // namespace
}  // namespace axg::morphology
