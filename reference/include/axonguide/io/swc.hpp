#pragma once
// Morphologies: one SWC file per neuron under DIR/morphologies (output.swc), following
// SONATA's rules for SWC: ids from 1, every parent before its children, a single-point
// soma (type 1) first, then the axon (type 3 is dendrite in SWC; the axon is type 2).
#include <filesystem>
#include <string>

#include "axonguide/engine/run.hpp"

namespace axg {

// Where an SWC file puts its origin: absolute coordinates (morphologies/), or the soma at
// the origin (the soma-centred copies that SONATA nodes name and place at their position).
enum class SwcFrame { kAbsolute, kSomaCentred };

// The SWC of neuron i: the soma, then the axon's tip after each step it grew (r.paths,
// output.paths); in an arbour scene, the soma and every point of its arbour. Coordinates
// and radii in micrometres (LU x kMicrometresPerLu when the scene declares no length
// unit). A soma-centred copy (arbour scenes) holds (point - soma) x micrometres per unit.
std::string swc_text(const RunResult& r, std::size_t i, SwcFrame frame = SwcFrame::kAbsolute);

// The radius given to every axon point, micrometres (SWC needs one; the model's axons
// have no thickness).
inline constexpr double kSwcAxonRadiusUm = 0.5;

// Writes morphologies/<id>.swc for every neuron and records their hashes in `info`, in id
// order. Needs r.paths.
void write_swc(const RunResult& r, const std::filesystem::path& dir, OutputInfo& info);

// Writes the soma-centred copies dir/sub/<id>.swc (arbour scenes; the folder that SONATA's
// components.morphologies_dir names), recorded in `info` as "sub/<id>.swc".
void write_centred_swc(const RunResult& r, const std::filesystem::path& dir, const std::string& sub,
                       OutputInfo& info);

}  // namespace axg
