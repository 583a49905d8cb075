#pragma once
// Morphometry (docs/methods.md §13): the statistics of Ramakers' cultured neurons
// (../shared/data/ramakers-culture/development.csv, as distributed with NETMORPH) for any
// SWC morphology, ours (a run's morphologies/) or measured elsewhere.
//
// Conventions, the data's:
//  - A neuron's axon is all of its type-2 neurites together (the data count one axon per
//    neuron, n = the neurons); each type-3 or type-4 neurite leaving the soma is one
//    dendrite.
//  - A segment is an unbranched stretch between two nodes: the soma, a branch point (a
//    sample with two or more children) or a tip (none). A terminal segment ends in a tip; an
//    intermediate one ends in a branch point (it starts at the soma or a branch point). A
//    branch point with k children counts once, so terminal segments - branch points = the
//    number of stems + the extra children of branch points of degree > 2.
//  - The mean intermediate segment length of a neurite without branch points is 0 (the data
//    list minima of 0.00 where the branch points' minimum is 0).
//  - Lengths are summed over the samples' straight pieces, in 3-D or, with a projection,
//    in the xy plane (cultures were measured in 2-D projection).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace axg::morphology {

struct Sample {
  std::int64_t id;
  int type;  // 1 soma, 2 axon, 3 basal dendrite, 4 apical dendrite; others are read and kept out of both
  double x, y, z, radius;
  std::int64_t parent;  // -1: a root
};

// One morphology: samples in file order, parents before children (read_swc checks it).
struct Morphology {
  std::string name;  // the file's stem
  std::vector<Sample> samples;
};

// Reads an SWC file. InputError (exit 2) names the file and the line for: a line without 7
// fields, a non-numeric field, an id given twice, a missing parent, a cycle, a parent that
// comes after its child, an empty file.
Morphology read_swc(const std::filesystem::path& path);
// The same from text; `origin` names it in messages.
Morphology parse_swc(const std::string& text, const std::string& origin);

// Every statistic of one neurite group (the axon, or one dendrite).
struct NeuriteStats {
  double total_length = 0;
  int branch_points = 0;
  int terminal_segments = 0;
  double mean_terminal_segment_length = 0;
  double mean_intermediate_segment_length = 0;
};

struct NeuronStats {
  std::string name;
  bool has_axon = false;
  NeuriteStats axon;
  std::vector<NeuriteStats> dendrites;
};

enum class Projection { kNone, kXY };

NeuronStats measure(const Morphology& m, Projection projection);

// The population rows of morphometry.csv, in the data's names and order:
// statistic, n, mean, sd (n - 1), se. Axon statistics over neurons with an axon; dendrite
// statistics over every dendrite; number_of_dendrites_per_neuron over every neuron.
struct Row {
  std::string statistic;
  std::size_t n;
  double mean, sd, se;
};
std::vector<Row> population(const std::vector<NeuronStats>& neurons);
const std::vector<std::string>& statistic_names();

// Sholl profile: per radius r = step, 2 step, ... up to the farthest sample, the number of
// the neurites' straight pieces that cross the sphere (circle, in projection) of radius r
// about the soma (one end inside, one outside; an end exactly on it counts as inside).
// type_set: 2 (axon) or 3 (dendrites: types 3 and 4).
std::vector<int> sholl(const Morphology& m, int type_set, double step, Projection projection);

// Reads every .swc of a folder (DIR/morphologies/ when DIR is a run folder), in the order of
// their names (numeric stems numerically). InputError when there is none.
std::vector<Morphology> read_folder(const std::filesystem::path& dir);

}  // namespace axg::morphology
