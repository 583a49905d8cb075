#pragma once
// One test body for every backend (STYLE §8): the scenes a backend must reproduce byte
// for byte, and the check itself. Used by the CPU-emulated pipeline (label accel) and by
// the GPU (label gpu).
#include <filesystem>
#include <string>
#include <vector>

#include "axonguide/core/random.hpp"
#include "axonguide/graph.hpp"
#include "support.hpp"

namespace axg::test {

struct NamedScene {
  std::string name;
  Scene scene;
};
inline void PrintTo(const NamedScene& s, std::ostream* os) { *os << s.name; }

// Test-name suffix of a scene: its name with every non-alphanumeric character as '_'.
struct SceneName {
  template <class Info>
  std::string operator()(const Info& info) const {
    std::string n = info.param.name;
    for (char& c : n)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return n;
  }
};

// Every bundled scene, every golden scene, the default, and one small variant per field,
// motion, scheme, boundary, steering model, sampler and contact rule. `small` shrinks the
// bundled scenes (the CPU emulation runs its kernels on one thread).
inline std::vector<NamedScene> backend_scenes(bool small) {
  std::vector<NamedScene> out;
  auto shrink = [&](Scene s) {
    if (small && s.neurons.count > 600) {
      const double f = 600.0 / static_cast<double>(s.neurons.count);
      s.neurons.count = 600;
      s.neurons.radius *= std::cbrt(f);
      s.axons.bounds_radius.reset();
    }
    return s;
  };
  const std::filesystem::path root(source_dir());
  for (const char* dir : {"scenes", "data/golden"}) {
    if (!std::filesystem::exists(root / dir)) continue;
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root / dir))
      if (e.path().extension() == ".json" && e.path().filename() == "scene.json") files.push_back(e.path());
      else if (e.path().extension() == ".json" && std::string(dir) == "scenes") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files)
      out.push_back({std::filesystem::relative(f, root).string(), shrink(load_scene_file(f.string()).scene)});
  }
  out.push_back({"builtin-default", Scene::builtin_default()});
  struct Variant {
    const char* name;
    void (*tweak)(Scene&);
  };
  const Variant variants[] = {
      {"direct-endpoint-trig-box", [](Scene& s) {
         s.guidance.model = GuidanceModel::kDirect;
         s.axons.contact = ContactRule::kEndpoint;
         s.neurons.sampler = Sampler::kTrig;
         s.neurons.shape = RegionShape::kBox;
       }},
      {"direct-sphere-coordinate", [](Scene& s) {
         s.guidance.model = GuidanceModel::kDirect;
         s.neurons.shape = RegionShape::kSphere;
         s.neurons.sampler = Sampler::kCoordinate;
         s.axons.bounds_radius = s.neurons.radius * 1.6;
       }},
      {"particles-vector-sum", [](Scene& s) { s.guidance.model = GuidanceModel::kVectorSum; }},
      {"particles-ballistic-collisions", [](Scene& s) {
         s.cues.particles.motion = Motion::kBallistic;
         s.cues.particles.collisions = true;
         s.cues.particles.radius = 0.05;
       }},
      {"grid-implicit-absorbing", [](Scene& s) { s.cues.field = FieldKind::kGrid; }},
      {"grid-implicit-reflecting-vector-sum", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.boundary = GridBoundary::kReflecting;
         s.guidance.model = GuidanceModel::kVectorSum;
       }},
      {"grid-explicit-absorbing", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.scheme = GridScheme::kExplicit;
       }},
      {"grid-explicit-reflecting", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.scheme = GridScheme::kExplicit;
         s.cues.grid.boundary = GridBoundary::kReflecting;
       }},
      {"analytic-snr", [](Scene& s) { s.cues.field = FieldKind::kAnalytic; }},
      {"analytic-vector-sum-normal", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.guidance.model = GuidanceModel::kVectorSum;
         s.neurons.sampler = Sampler::kNormal;
       }},
  };
  for (const Variant& v : variants) {
    Scene s = Scene::builtin_default();
    s.neurons.count = 400;
    s.neurons.radius = 2.5 * std::cbrt(4.0);
    s.steps = 50;
    s.cues.grid.spacing = 0.25;
    s.analysis.bfs_sources = {0, 1, 2, 3};
    s.output.paths = true;
    v.tweak(s);
    out.push_back({v.name, s});
  }
  return out;
}

// Random cue scenes for the RapidCheck comparison.
inline rc::Gen<Scene> gen_cue_scene() {
  return rc::gen::exec([] {
    Scene s = *gen_direct_scene();
    s.neurons.count = std::min<std::uint64_t>(s.neurons.count, 200);
    s.steps = std::min<std::uint32_t>(s.steps, 30);
    s.guidance.model = *rc::gen::element(GuidanceModel::kDirect, GuidanceModel::kSnr, GuidanceModel::kVectorSum);
    s.cues.field = *rc::gen::element(FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic);
    s.cues.random_sources.count = *rc::gen::inRange<std::uint32_t>(1, 5);
    s.cues.random_sources.emission = *rc::gen::inRange(0, 300) / 2.0;
    s.cues.particles.motion = *rc::gen::element(Motion::kBrownian, Motion::kBallistic);
    s.cues.particles.collisions = *rc::gen::arbitrary<bool>();
    s.cues.grid.spacing = std::max(0.2, s.bounds_radius() / 12);
    s.cues.grid.scheme = *rc::gen::element(GridScheme::kExplicit, GridScheme::kImplicit);
    s.cues.grid.boundary = *rc::gen::element(GridBoundary::kAbsorbing, GridBoundary::kReflecting);
    s.analysis.bfs_sources = {0};
    return s;
  });
}

// The outputs of `make` equal the reference's, byte for byte.
inline void expect_same_as_reference(const Scene& scene, const EngineFactory& make, const std::string& name) {
  const auto reference = run_hashes(scene, 2);
  const auto backend = run_hashes(scene, 2, make);
  EXPECT_EQ(backend, reference) << name;
}

}  // namespace axg::test
