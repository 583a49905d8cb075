#pragma once
// SONATA output (output.sonata; docs/guide.md §1.2): the network as the neuroscience
// tools read it. Under dir/network/: nodes.h5 (population "axonguide"), edges.h5
// (population "axonguide_to_axonguide", one edge per connected axon, in connections.csv
// order), node_types.csv, edge_types.csv and circuit_config.json. Positions and lengths
// in µm, delays in ms from output.conduction_speed. In an arbour scene each node also names
// its morphology, a soma-centred SWC copy under network/morphologies/ (circuit_config's
// components.morphologies_dir). Each file is written to a temporary name and renamed; the
// bytes are a function of the run alone (no HDF5 timestamps).
#include <filesystem>

#include "axonguide/engine/run.hpp"

namespace axg {

// Writes the five files (and an arbour scene's morphology copies) and appends
// ("network/NAME", sha256) for each to info.files. Throws RunError on any I/O or HDF5
// failure.
void write_sonata(const RunResult& r, const std::filesystem::path& dir, OutputInfo& info);

// The SONATA files relative to the run folder, in the order write_sonata writes them.
inline constexpr const char* kSonataFiles[] = {"network/nodes.h5", "network/edges.h5", "network/node_types.csv",
                                               "network/edge_types.csv", "network/circuit_config.json"};

}  // namespace axg
