#include "axonguide/model/sensing.hpp"

#include <fmt/format.h>

#include "axonguide/model/cues.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

void read_sensing_keys(ObjectReader& r, SensingKeys& g) {
  r.number("growth_cone_width", g.growth_cone_width, positive());
  r.number("sensing_radius", g.sensing_radius, positive());
}

void read_molecule_keys(ObjectReader& r, MoleculeKeys& c) {
  r.optional_number("molecule_amount", c.molecule_amount, positive());
}

void write_sensing_keys(const SensingKeys& g, nlohmann::json& j) {
  j["growth_cone_width"] = g.growth_cone_width;
  j["sensing_radius"] = g.sensing_radius;
}

void write_molecule_keys(const MoleculeKeys& c, nlohmann::json& j) {
  if (c.molecule_amount) j["molecule_amount"] = *c.molecule_amount;  // only when given
}

void check_molecule_amount(const Scene& s) {
  const auto& c = s.cues;
  if (c.molecule_amount && s.units.length == "um" && s.units.concentration != "CU")
    throw InputError(fmt::format(
        "scene: cues.molecule_amount = {}: the scene declares physical units ({}), which fix one molecule at {:.6g} "
        "{} um^3; remove the key (it is for scenes without physical length or concentration units)",
        *c.molecule_amount, s.units.describe(), molecule_amount_from_units(s.units), s.units.concentration));
}

double molecule_amount_from_units(const Units& units) {
  // One molecule is 1 / 0.602214076 nM um^3 (1 nM = 6.02214076e14 per litre, a litre
  // 10^15 um^3); in the scene's units, with CU read as nM and LU as kMicrometresPerLu um.
  const double nm_per_unit = units.concentration == "pM" ? 1e-3 : (units.concentration == "uM" ? 1e3 : 1.0);
  const double um = units.micrometres();
  return 1.0 / 0.602214076 / nm_per_unit / (um * um * um);
}

double Scene::molecule_amount() const {
  return cues.molecule_amount ? *cues.molecule_amount : molecule_amount_from_units(units);
}

core::SenseParams sense_params(const Scene& scene) {
  core::SenseParams p{};
  const double r = scene.guidance.sensing_radius;
  const double volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
  const double m = scene.molecule_amount();
  p.field = scene.cues.field;
  if (scene.guidance.model == GuidanceModel::kSourceVectorSum) p.sensing = core::ParticleSensing::kGather;
  else if (scene.cues.particles.molecules && scene.guidance.model == GuidanceModel::kSnr &&
           scene.guidance.noise == NoiseForm::kCount)
    p.sensing = core::ParticleSensing::kMolecules;
  else p.sensing = core::ParticleSensing::kEstimate;
  p.radius = r;
  p.radius2 = r * r;
  p.inv_radius = 1.0 / r;
  p.molecule = m;
  p.c_per_particle = scene.cues.particles.amount / volume;
  p.count_mean_scale = volume * r / (5.0 * m);
  p.count_var_scale = volume / (5.0 * m);
  p.cone_width = scene.guidance.growth_cone_width;
  p.analytic_rmin = 1e-3;
  p.imposed = imposed_params(scene);
  // The count form's target is the molecules in the sensing ball (SPEC §3.5).
  p.ball = scene.guidance.model == GuidanceModel::kSnr && scene.guidance.noise == NoiseForm::kCount;
  return p;
}

}  // namespace axg
