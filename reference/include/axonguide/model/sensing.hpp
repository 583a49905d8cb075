#pragma once
// Sensing (SPEC §3.4; docs/methods.md §2.6): the growth cone's physical sensing keys
// (guidance.sensing_radius and growth_cone_width; cues.molecule_amount, the amount of one
// molecule), their reading and canonical form, and the parameters that core/sensing.hpp
// and the count decision of core/steering.hpp get.
#include <optional>

#include <nlohmann/json.hpp>

#include "axonguide/core/cues.hpp"

namespace axg {

struct Scene;
struct Units;
class ObjectReader;

struct SensingKeys {
  double growth_cone_width = 0.1;  // w, length units
  double sensing_radius = 0.5;     // r, length units
};

// m: concentration units x length^3 of one molecule, a physical quantity (the count noise
// form counts molecules, and molecule-resolved particles are molecules). nullopt: derived
// from the units (molecule_amount_from_units).
struct MoleculeKeys {
  std::optional<double> molecule_amount;
};

void read_sensing_keys(ObjectReader& guidance, SensingKeys& keys);
void read_molecule_keys(ObjectReader& cues, MoleculeKeys& keys);
void write_sensing_keys(const SensingKeys& keys, nlohmann::json& guidance);
void write_molecule_keys(const MoleculeKeys& keys, nlohmann::json& cues);
// cues.molecule_amount is refused in a scene whose physical units fix the molecule.
void check_molecule_amount(const Scene& scene);

// One molecule in a scene's units: 1 nM is 0.602214076 molecules per um^3, with CU read as
// nM and LU as kMicrometresPerLu um where they are not declared.
double molecule_amount_from_units(const Units& units);

core::SenseParams sense_params(const Scene& scene);

}  // namespace axg
