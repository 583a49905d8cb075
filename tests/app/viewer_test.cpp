// Seeing the network: ParaView files read back with VTK's own reader, the browser page
// rendered by headless Chromium (no console errors, a non-blank screenshot), the page's
// report of missing files, and the matplotlib plots.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <tuple>
#include <sstream>

#include <nlohmann/json.hpp>

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

// A run's page in headless Chromium: the DOM it settles to, and its screenshot's share of
// pixels that differ from the background and number of colours (tests/app/pixels.py).
struct RenderedPage {
  std::string dom;
  double fraction = 0;
  int colours = 0;
  bool shot = false;
};

RenderedPage render_page(const test::TempDir& tmp, const fs::path& run) {
  RenderedPage p;
  const std::string url = "file://" + (run / "view.html").string();
  p.dom = shell(fmt::format("chromium {} --user-data-dir={} --dump-dom {}", kChromiumFlags,
                            (tmp.path() / "profile1").string(), url))
              .text;
  const fs::path shot = tmp.path() / "shot.png";
  shell(fmt::format("chromium {} --user-data-dir={} --screenshot={} {}", kChromiumFlags,
                    (tmp.path() / "profile2").string(), shot.string(), url));
  p.shot = fs::exists(shot);
  if (!p.shot) return p;
  const Out px = shell(fmt::format("/usr/bin/python3 {}/tests/app/pixels.py {}", test::source_dir(), shot.string()));
  if (std::sscanf(px.text.c_str(), "%lf %d", &p.fraction, &p.colours) != 2) p.colours = -1;
  return p;
}

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
  const RenderedPage page = render_page(tmp, run);
  EXPECT_NE(page.dom.find("id=\"axg-status\">ready: 150 neurons"), std::string::npos) << page.dom.substr(0, 4000);
  EXPECT_NE(page.dom.find("id=\"axg-errors\" hidden=\"\"></div>"), std::string::npos) << "page errors: " << page.dom;
  EXPECT_EQ(page.dom.find("Uncaught"), std::string::npos);
  ASSERT_TRUE(page.shot);
  ASSERT_GE(page.colours, 0) << "pixels.py gave no statistics";
  EXPECT_GT(page.fraction, 0.05) << "the canvas looks blank";
  EXPECT_GT(page.colours, 50) << "too few colours for somas, axons and particles";
}

TEST(viewer, PageSaysWhatIsMissing) {
  test::TempDir tmp;
  std::ofstream(tmp.path() / "bare.json") << R"({"steps": 10, "neurons": {"count": 50, "region": {"radius": 2}},
      "guidance": {"model": "direct"}, "analysis": {"bfs_sources": [], "components": false}})";
  const fs::path run = tmp.path() / "run";
  ASSERT_EQ(shell(fmt::format("{} run {} --out {} -q", test::binary(), (tmp.path() / "bare.json").string(), run.string())).code, 0);
  const Out v = shell(fmt::format("{} view {}", test::binary(), run.string()));
  ASSERT_EQ(v.code, 0) << v.text;
  EXPECT_NE(v.text.find("missing bfs.csv"), std::string::npos) << v.text;
  const std::string page = test::read_file(run / "view.html");
  for (const char* m : {"missing: bfs.csv", "no paths.csv"}) EXPECT_NE(page.find(m), std::string::npos) << m;
  EXPECT_EQ(shell(fmt::format("{} view {}", test::binary(), (tmp.path() / "nope").string())).code, 2);
}

// The list of files a run's manifest holds, re-hashed after a file was edited: the
// folder verifies, but its data is not a run's.
void rehash(const fs::path& run, const std::string& name) {
  auto m = nlohmann::json::parse(test::read_file(run / "manifest.json"));
  m["files"][name]["sha256"] = sha256_file(run / name);
  std::ofstream(run / "manifest.json") << m.dump(2);
}

void replace_line(const fs::path& file, int line, const std::string& text) {
  std::istringstream in(test::read_file(file));
  std::string out, l;
  for (int k = 1; std::getline(in, l); ++k) out += (k == line ? text : l) + "\n";
  std::ofstream(file, std::ios::binary) << out;
}

// An arbour run (issue 41): every point drawn from the SWC sample it hangs on (one segment
// per paths.csv row, but for each stem's first point, which hangs on the soma), coloured by
// centrifugal order; a point listed before its parent is refused, not drawn.
TEST(viewer, ArbourPageDrawsEveryConeByOrder) {
  if (!has("command -v chromium")) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh)";
  if (!has("/usr/bin/python3 -c 'import PIL'")) GTEST_SKIP() << "python3-pil is not installed";
  test::TempDir tmp;
  auto scene = nlohmann::json::parse(test::read_file(fs::path(test::source_dir()) / "scenes" / "culture.json"));
  scene["neurons"]["count"] = 40;
  scene["neurons"]["region"]["radius"] = 400;
  scene["output"] = {{"paths", true}};
  std::ofstream(tmp.path() / "culture.json") << scene.dump();
  const fs::path run = tmp.path() / "run";
  ASSERT_EQ(shell(fmt::format("{} run {} --out {} -q", test::binary(), (tmp.path() / "culture.json").string(), run.string())).code, 0);
  std::size_t rows = 0, stems = 0;  // stems: the rows that hang on the soma (sample 1)
  {
    std::istringstream in(test::read_file(run / "paths.csv"));
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "id,cone,parent,type,order,step,x,y,z,parent_sample");
    for (; std::getline(in, line); ++rows) stems += line.substr(line.rfind(',') + 1) == "1";
  }
  ASSERT_GT(rows, 1000u);
  const Out v = shell(fmt::format("{} view {}", test::binary(), run.string()));
  ASSERT_EQ(v.code, 0) << v.text;
  const RenderedPage page = render_page(tmp, run);
  EXPECT_NE(page.dom.find(fmt::format("id=\"axg-status\">ready: 40 neurons, {} arbour segments", rows - stems)),
            std::string::npos)
      << page.dom.substr(0, 4000);
  EXPECT_NE(page.dom.find("id=\"axg-errors\" hidden=\"\"></div>"), std::string::npos) << "page errors: " << page.dom;
  EXPECT_NE(page.dom.find("8+ order"), std::string::npos) << "the order legend";
  ASSERT_TRUE(page.shot);
  ASSERT_GE(page.colours, 0) << "pixels.py gave no statistics";
  EXPECT_GT(page.fraction, 0.05) << "the canvas looks blank";
  EXPECT_GT(page.colours, 50) << "too few colours for arbours coloured by order";
  // A daughter listed before its parent (the file edited, the manifest re-hashed): refused.
  std::istringstream in(test::read_file(run / "paths.csv"));
  std::string line;
  int number = 0, daughter = 0;
  while (std::getline(in, line) && !daughter) {
    ++number;
    if (number > 1 && line.find(",-1,") == std::string::npos) daughter = number;
  }
  ASSERT_GT(daughter, 0);
  replace_line(run / "paths.csv", 2, line);
  rehash(run, "paths.csv");
  const Out bad = shell(fmt::format("{} view {}", test::binary(), run.string()));
  EXPECT_EQ(bad.code, 2) << bad.text;
  EXPECT_NE(bad.text.find("before its parent"), std::string::npos) << bad.text;
}

// view draws only whole runs, only the files they list, and only a run's data.
TEST(viewer, RefusesWhatIsNotARun) {
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  auto view = [&](const fs::path& d) { return shell(fmt::format("{} view {}", test::binary(), d.string())); };
  // An empty folder; a folder whose files were deleted or changed.
  fs::create_directories(tmp.path() / "empty");
  Out v = view(tmp.path() / "empty");
  EXPECT_EQ(v.code, 2);
  EXPECT_NE(v.text.find("not a whole run"), std::string::npos) << v.text;
  const fs::path copy = tmp.path() / "copy";
  fs::copy(run, copy, fs::copy_options::recursive);
  fs::remove(copy / "paths.csv");
  v = view(copy);
  EXPECT_EQ(v.code, 2);
  EXPECT_NE(v.text.find("paths.csv: missing"), std::string::npos) << v.text;
  // NaN somas, unknown statuses and targets that are not neuron ids, with the manifest
  // re-hashed so that only the data says it is not a run's.
  const std::string original = test::read_file(run / "neurons.csv");
  for (const auto& [row, why] : {std::pair{"0,nan,0,0,0.25,growing,0,0,0,0,0,-1", "not finite"},
                                 std::pair{"0,0,0,0,0.25,flying,0,0,0,0,0,-1", "status \"flying\""},
                                 std::pair{"0,0,0,0,0.25,connected,0,0,0,0,0,150", "target 150 is not a neuron id"},
                                 std::pair{"0,0,0,0,0.25,connected,0,0,0,0,0,-7", "target -7 is not a neuron id"},
                                 std::pair{"5,0,0,0,0.25,growing,0,0,0,0,0,-1", "id 5 where 0 belongs"}}) {
    std::ofstream(run / "neurons.csv", std::ios::binary) << original;
    replace_line(run / "neurons.csv", 2, row);
    rehash(run, "neurons.csv");
    v = view(run);
    EXPECT_EQ(v.code, 2) << row;
    EXPECT_NE(v.text.find(why), std::string::npos) << v.text;
  }
  std::ofstream(run / "neurons.csv", std::ios::binary) << original;
  rehash(run, "neurons.csv");
  // The other files it reads: too few columns (it read past the row, and crashed), and
  // numbers no run writes.
  for (const auto& [file, text, why] :
       {std::tuple{"paths.csv", "id\n0\n0\n1\n", "a header of 1 columns"},
        std::tuple{"paths.csv", "id,step,x,y,z\n0,0,0,0,0\n-3,1,0,0,0\n", "-3 is not an integer"},
        std::tuple{"paths.csv", "id,step,x,y,z\n0,0,nan,0,0\n", "\"nan\" is not a finite number"},
        std::tuple{"bfs.csv", "id,level,component\n1e300,0,0\n", "is not an integer"}}) {
    const std::string before = test::read_file(run / file);
    std::ofstream(run / file, std::ios::binary) << text;
    rehash(run, file);
    v = view(run);
    EXPECT_EQ(v.code, 2) << file << ": " << v.text;
    EXPECT_NE(v.text.find(why), std::string::npos) << file << ": " << v.text;
    std::ofstream(run / file, std::ios::binary) << before;
    rehash(run, file);
  }
}

// plot: every failure of its helper is one line and exit 2 or 3, never a traceback.
TEST(viewer, PlotFailuresAreOneLine) {
  if (!has("/usr/bin/python3 -c 'import matplotlib'")) GTEST_SKIP() << "python3-matplotlib is not installed";
  test::TempDir tmp;
  const fs::path run = small_run(tmp);
  for (const auto& [file, line] : {std::pair{"stats.csv", std::string("zero,1,2,3,4")},
                                   std::pair{"stats.csv", std::string("\xff\xfe\x01,1")},
                                   std::pair{"connections.csv", std::string("0,99999,3,1.5")}}) {
    const std::string before = test::read_file(run / file);
    replace_line(run / file, 2, line);
    rehash(run, file);
    const Out p = shell(fmt::format("{} plot {}", test::binary(), run.string()));
    EXPECT_EQ(p.code, 2) << p.text;
    EXPECT_EQ(p.text.find("Traceback"), std::string::npos) << p.text;
    EXPECT_NE(p.text.find("axonguide: plot: "), std::string::npos) << p.text;
    std::ofstream(run / file, std::ios::binary) << before;
    rehash(run, file);
  }
  // Not a run at all: refused before the helper starts.
  fs::create_directories(tmp.path() / "empty");
  const Out p = shell(fmt::format("{} plot {}", test::binary(), (tmp.path() / "empty").string()));
  EXPECT_EQ(p.code, 2);
  EXPECT_NE(p.text.find("not a whole run"), std::string::npos) << p.text;
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
