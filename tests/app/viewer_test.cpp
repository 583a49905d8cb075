// Seeing the network: ParaView files read back with VTK's own reader, the browser page
// rendered by headless Chromium (no console errors, a non-blank screenshot), the page's
// report of missing files, and the matplotlib plots.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>

#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

struct Out {
  int code;
  std::string text;
};

Out shell(const std::string& cmd) {
  Out o{0, {}};
  std::FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) o.text.append(buf, n);
  const int status = pclose(p);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

bool has(const std::string& program_test) { return shell(program_test).code == 0; }

const char* kChromiumFlags =
    "--headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --disable-background-networking "
    "--disable-component-update --disable-sync --no-first-run --window-size=900,650 --virtual-time-budget=20000";

// A small cue run with paths, particle frames and the ParaView files.
fs::path small_run(const test::TempDir& tmp) {
  std::ofstream(tmp.path() / "scene.json") << R"({"steps": 30, "neurons": {"count": 150, "region": {"radius": 2.9}},
      "cues": {"sources": [{"kind": "attractant"}, {"kind": "repellent"}]},
      "output": {"vtk": true, "frames_every": 10}})";
  const Out r = shell(fmt::format("{} run {} --out {} -q", test::binary(), (tmp.path() / "scene.json").string(),
                                  (tmp.path() / "run").string()));
  EXPECT_EQ(r.code, 0) << r.text;
  return tmp.path() / "run";
}

TEST(viewer, ParaViewFilesReadBackWithVtk) {
  if (!has("/usr/bin/python3 -c 'import vtk'")) GTEST_SKIP() << "python3-vtk9 is not installed (scripts/install-deps.sh)";
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  ASSERT_TRUE(fs::exists(run / "growth.pvd"));
  const Out r = shell(fmt::format("/usr/bin/python3 {}/tests/app/check_vtk.py {}", test::source_dir(), run.string()));
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_NE(r.text.find("OK 150 somas, 2 sources"), std::string::npos) << r.text;
}

TEST(viewer, BrowserPageRendersTheSceneWithoutErrors) {
  if (!has("command -v chromium")) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh)";
  if (!has("/usr/bin/python3 -c 'import PIL'")) GTEST_SKIP() << "python3-pil is not installed";
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  const Out v = shell(fmt::format("{} view {}", test::binary(), run.string()));
  ASSERT_EQ(v.code, 0) << v.text;
  const std::string url = "file://" + (run / "view.html").string();
  const Out dom = shell(fmt::format("chromium {} --user-data-dir={} --dump-dom {}", kChromiumFlags,
                                    (tmp.path() / "profile1").string(), url));
  EXPECT_NE(dom.text.find("id=\"axg-status\">ready: 150 neurons"), std::string::npos) << dom.text.substr(0, 4000);
  EXPECT_NE(dom.text.find("id=\"axg-errors\" hidden=\"\"></div>"), std::string::npos) << "page errors: " << dom.text;
  EXPECT_EQ(dom.text.find("Uncaught"), std::string::npos);
  const fs::path shot = tmp.path() / "shot.png";
  shell(fmt::format("chromium {} --user-data-dir={} --screenshot={} {}", kChromiumFlags, (tmp.path() / "profile2").string(),
                    shot.string(), url));
  ASSERT_TRUE(fs::exists(shot));
  const Out px = shell(fmt::format("/usr/bin/python3 {}/tests/app/pixels.py {}", test::source_dir(), shot.string()));
  double fraction = 0;
  int colours = 0;
  ASSERT_EQ(std::sscanf(px.text.c_str(), "%lf %d", &fraction, &colours), 2) << px.text;
  EXPECT_GT(fraction, 0.05) << "the canvas looks blank";
  EXPECT_GT(colours, 50) << "too few colours for somas, axons and particles";
}

TEST(viewer, PageSaysWhatIsMissing) {
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  for (const char* f : {"bfs.csv", "paths.csv", "manifest.json", "connections.csv"}) fs::remove(run / f);
  const Out v = shell(fmt::format("{} view {}", test::binary(), run.string()));
  ASSERT_EQ(v.code, 0) << v.text;
  EXPECT_NE(v.text.find("missing bfs.csv"), std::string::npos) << v.text;
  const std::string page = test::read_file(run / "view.html");
  for (const char* m : {"missing: bfs.csv", "missing: manifest.json", "missing: connections.csv", "no paths.csv"})
    EXPECT_NE(page.find(m), std::string::npos) << m;
  EXPECT_EQ(shell(fmt::format("{} view {}", test::binary(), (tmp.path() / "nope").string())).code, 2);
}

TEST(viewer, PlotWritesEveryPng) {
  if (!has("/usr/bin/python3 -c 'import matplotlib'")) GTEST_SKIP() << "python3-matplotlib is not installed";
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  const Out p = shell(fmt::format("{} plot {}", test::binary(), run.string()));
  ASSERT_EQ(p.code, 0) << p.text;
  for (const char* f : {"growth.png", "in_degree.png", "bfs_levels.png", "axon_lengths.png", "projection.png"})
    EXPECT_GT(fs::file_size(run / f), 1000u) << f;
}

}  // namespace
}  // namespace axg
