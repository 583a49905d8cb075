// Every output writer spells a NaN one way: "nan" in the text files (never "-nan", "NaN" or
// a payload), the quiet NaN 0x7ff8000000000000 in the VTK files' binary arrays, whatever
// sign and payload the value had (x86 and NVIDIA produce different NaNs).
#include <gtest/gtest.h>

#include <strings.h>

#include <cstring>
#include <regex>
#include <string>
#include <vector>

#include "axonguide/io/canonical_nan.hpp"
#include "support.hpp"

namespace axg {
namespace {

using core::bits_of;
using core::double_of;

// Six NaNs: the default quiet one, negative, with payloads, and a signalling one.
const double kNaNs[] = {double_of(0x7ff8000000000000ull), double_of(0xfff8000000000000ull),
                        double_of(0x7ff8000000000123ull), double_of(0xfff80000deadbeefull),
                        double_of(0x7ff0000000000001ull), double_of(0xfff0000000000abcull)};

// Occurrences of "nan" in any case; fails on every spelling but the canonical one.
std::size_t count_nan(const std::string& text, const std::string& file) {
  std::size_t count = 0;
  for (std::size_t i = 0; i + 3 <= text.size(); ++i) {
    const std::string word = text.substr(i, 3);
    if (strcasecmp(word.c_str(), "nan") != 0) continue;
    ++count;
    EXPECT_EQ(word, "nan") << file << " at byte " << i;
    EXPECT_FALSE(i > 0 && text[i - 1] == '-') << file << ": \"-nan\" at byte " << i;
    EXPECT_FALSE(i + 3 < text.size() && text[i + 3] == '(') << file << ": a NaN payload at byte " << i;
  }
  return count;
}

// The NaNs of a .vtp file's Float64 arrays (appended raw data, UInt64 block headers); fails
// on any NaN that is not the canonical one.
std::size_t count_vtk_nan(const std::string& data, const std::string& file) {
  const std::string marker = "<AppendedData encoding=\"raw\">\n   _";
  const std::size_t base = data.find(marker);
  EXPECT_NE(base, std::string::npos) << file;
  if (base == std::string::npos) return 0;
  const std::size_t start = base + marker.size();
  const std::string xml = data.substr(0, base);
  const std::regex array(R"re(<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="\d+" format="appended" offset="(\d+)"/>)re");
  std::size_t count = 0, float_arrays = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), array); it != std::sregex_iterator(); ++it) {
    if ((*it)[1] != "Float64") continue;
    ++float_arrays;
    const std::size_t at = start + std::stoull((*it)[3]);
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, data.data() + at, 8);
    for (std::uint64_t k = 0; k < bytes / 8; ++k) {
      std::uint64_t b;
      std::memcpy(&b, data.data() + at + 8 + 8 * k, 8);
      if ((b & 0x7fffffffffffffffull) <= 0x7ff0000000000000ull) continue;
      ++count;
      EXPECT_EQ(b, kCanonicalNanBits) << file << ", array " << (*it)[2] << ", value " << k;
    }
  }
  EXPECT_GT(float_arrays, 0u) << file;
  return count;
}

TEST(output, CanonicalLeavesOtherValuesAlone) {
  for (const double x : {0.0, -0.0, 1.5, -2.25e-310, 1e308, std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity()})
    EXPECT_EQ(bits_of(canonical(x)), bits_of(x)) << x;
  for (const double x : kNaNs) EXPECT_EQ(bits_of(canonical(x)), kCanonicalNanBits) << std::hex << bits_of(x);
}

TEST(output, EveryWriterSpellsNanOneWay) {
  Scene s = Scene::builtin_default();
  s.neurons.count = 60;
  s.steps = 7;
  s.output.paths = true;
  s.output.vtk = true;
  s.output.frames_every = 3;
  RunResult r = run_scene(s, {});
  ASSERT_FALSE(r.cues.empty()) << "the default scene has no sources: sources.csv is not written";
  ASSERT_FALSE(r.frames.empty()) << "no particle frames: particles.csv is not written";
  ASSERT_FALSE(r.frames[0].pos.empty());
  ASSERT_GE(r.paths.size(), 2u);
  ASSERT_TRUE(r.graph.bfs.has_value());
  ASSERT_FALSE(r.graph.component.empty());
  const double* n = kNaNs;

  r.soma[0] = {n[0], n[1], n[2]};            // neurons.csv 3, graph.graphml 3, somas.vtp 3
  r.neurons.tip[1] = {n[3], n[4], 1.0};      // neurons.csv 2
  r.neurons.length[2] = n[5];                // neurons.csv 1, connections.csv 1, graph.graphml 1
  r.neurons.target[2] = 3;
  r.neurons.status[2] = core::AxonStatus::kConnected;
  r.neurons.steps[4] = std::max<std::uint32_t>(r.neurons.steps[4], 1);
  r.paths[1][4] = {n[1], n[3], n[5]};        // paths.csv 3, every axons_*.vtp from step 1 on: 3
  r.cues[0].position.x = n[2];               // sources.csv 4, sources.vtp 3
  r.cues[0].emission = n[4];
  r.cues[0].kd = n[0];
  r.cues[0].max_c = n[5];
  r.frames[0].pos[0] = {n[3], n[1], n[2]};   // particles.csv 3

  test::TempDir dir;
  write_outputs(r, dir.path(), "test", 1, {});
  const auto read = [&](const std::string& name) { return test::read_file(dir.path() / name); };
  EXPECT_EQ(count_nan(read("neurons.csv"), "neurons.csv"), 6u);
  EXPECT_EQ(count_nan(read("connections.csv"), "connections.csv"), 1u);
  EXPECT_EQ(count_nan(read("stats.csv"), "stats.csv"), 0u);  // integers only
  EXPECT_EQ(count_nan(read("bfs.csv"), "bfs.csv"), 0u);      // integers only
  EXPECT_EQ(count_nan(read("paths.csv"), "paths.csv"), 3u);
  EXPECT_EQ(count_nan(read("sources.csv"), "sources.csv"), 4u);
  EXPECT_EQ(count_nan(read("particles.csv"), "particles.csv"), 3u);
  EXPECT_EQ(count_nan(read("graph.graphml"), "graph.graphml"), 4u);
  EXPECT_EQ(count_nan(read("growth.pvd"), "growth.pvd"), 0u);

  EXPECT_EQ(count_vtk_nan(read("vtk/somas.vtp"), "somas.vtp"), 3u);
  EXPECT_EQ(count_vtk_nan(read("vtk/sources.vtp"), "sources.vtp"), 3u);
  std::size_t axon_files = 0, particle_files = 0, particle_nans = 0;
  for (const auto& e : test::fs::directory_iterator(dir.path() / "vtk")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("axons_", 0) == 0) {
      ++axon_files;
      const std::size_t found = count_vtk_nan(read("vtk/" + name), name);
      EXPECT_EQ(found, name == "axons_000000.vtp" ? 0u : 3u) << name;
    } else if (name.rfind("particles_", 0) == 0) {
      ++particle_files;
      particle_nans += count_vtk_nan(read("vtk/" + name), name);
    }
  }
  EXPECT_GE(axon_files, 2u);
  EXPECT_GE(particle_files, 1u);
  EXPECT_GE(particle_nans, 3u);
}

}  // namespace
}  // namespace axg
