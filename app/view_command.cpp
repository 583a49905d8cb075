// `axonguide view DIR` writes DIR/view.html: a self-contained page (three.js from the npm
// package, inlined as data: modules through an import map; the run's data embedded as
// JSON with base64 typed arrays). `axonguide plot DIR` writes PNG plots with matplotlib.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/io/csv.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/io/neurons_csv.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/validate/report.hpp"
#include "assets.hpp"
#include "commands.hpp"

namespace axg::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Above these, the page is thinned (and says so): it must stay loadable and smooth.
constexpr std::size_t kMaxPathPoints = 1000000;
constexpr std::size_t kMaxFrameParticles = 200000;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw RunError(fmt::format("view: cannot read {}", p.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string base64(const void* data, std::size_t n) {
  static constexpr char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const unsigned v = (b[i] << 16) | (b[i + 1] << 8) | b[i + 2];
    out += t[v >> 18], out += t[(v >> 12) & 63], out += t[(v >> 6) & 63], out += t[v & 63];
  }
  if (i + 1 == n) {
    const unsigned v = b[i] << 16;
    out += t[v >> 18], out += t[(v >> 12) & 63], out += "==";
  } else if (i + 2 == n) {
    const unsigned v = (b[i] << 16) | (b[i + 1] << 8);
    out += t[v >> 18], out += t[(v >> 12) & 63], out += t[(v >> 6) & 63], out += '=';
  }
  return out;
}

template <class T>
std::string b64(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

// A CSV file as a header index and rows of cells.
struct Csv {
  fs::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return static_cast<int>(k);
    return -1;
  }
  [[noreturn]] void refuse(std::size_t row, const std::string& why) const {
    throw InputError(fmt::format("view: {}: line {}: {}: not a run's data", path.string(), row + 2, why));
  }
  // Cell (row, c) as a finite number; anything else is not a run's data.
  double number(std::size_t row, int c) const {
    const std::optional<double> v = parse_number(rows[row][static_cast<std::size_t>(c)]);
    if (!v || !std::isfinite(*v))
      refuse(row, fmt::format("\"{}\" is not a finite number", printable(rows[row][static_cast<std::size_t>(c)])));
    return *v;
  }
  // Cell (row, c) as an integer in [lo, hi].
  long long integer(std::size_t row, int c, long long lo, long long hi) const {
    const double v = number(row, c);
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi) && v == std::floor(v)))
      refuse(row, fmt::format("{} is not an integer in [{}, {}]", v, lo, hi));
    return static_cast<long long>(v);
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string c;
  while (std::getline(ss, c, ',')) cells.push_back(c);
  return cells;
}

// False when the file is absent; InputError when a row has fewer cells than the header
// (a truncated or hand-edited file).
bool load_csv(const fs::path& p, Csv& out, std::size_t columns) {
  std::ifstream in(p);
  if (!in) return false;
  out.path = p;
  std::string line;
  if (!std::getline(in, line)) return false;
  out.header = split(line);
  if (out.header.size() < columns)
    throw InputError(fmt::format("view: {}: a header of {} columns, where a run writes at least {}: not a run's data",
                                 p.string(), out.header.size(), columns));
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    out.rows.push_back(split(line));
    if (out.rows.back().size() < out.header.size())
      throw InputError(fmt::format("view: {}: line {} has {} cells, the header has {}", p.string(), number,
                                   out.rows.back().size(), out.header.size()));
  }
  return true;
}

// The viewer's files: the ones compiled into the command, or those in AXG_VIEWER_DIR (and
// three.js in AXG_THREE_DIR) when set, for working on the page without rebuilding.
struct ViewerFiles {
  std::string page, css, view_js, three_module, three_core, orbit;
};

ViewerFiles viewer_files() {
  ViewerFiles v;
  if (const char* dir = std::getenv("AXG_VIEWER_DIR"); dir && *dir) {
    v.page = read_text(fs::path(dir) / "template.html");
    v.css = read_text(fs::path(dir) / "view.css");
    v.view_js = read_text(fs::path(dir) / "view.js");
  } else {
    v.page = assets::template_html(), v.css = assets::view_css(), v.view_js = assets::view_js();
  }
  const char* three_env = std::getenv("AXG_THREE_DIR");
  if ((three_env && *three_env) || assets::three_module().empty()) {
    const fs::path three = three_env && *three_env ? fs::path(three_env) : data_dir() / "three";
    if (!fs::exists(three / "build" / "three.module.js"))
      throw RunError(fmt::format("view: this build has no three.js compiled in and none is at {} (build after "
                                 "scripts/install-deps.sh, or set AXG_THREE_DIR to an installed three package)",
                                 three.string()));
    v.three_module = read_text(three / "build" / "three.module.js");
    v.three_core = read_text(three / "build" / "three.core.js");
    v.orbit = read_text(three / "examples" / "jsm" / "controls" / "OrbitControls.js");
  } else {
    v.three_module = assets::three_module(), v.three_core = assets::three_core(), v.orbit = assets::orbit_controls();
  }
  return v;
}

// three.js as data: modules. three.module.js imports './three.core.js', which has no
// meaning inside a data: URL: it is remapped to the bare name "three/core".
std::string import_map(const ViewerFiles& v) {
  std::string module = v.three_module;
  for (std::size_t p; (p = module.find("'./three.core.js'")) != std::string::npos;) module.replace(p, 17, "'three/core'");
  auto url = [](const std::string& src) { return "data:text/javascript;base64," + base64(src.data(), src.size()); };
  json m;
  m["imports"] = {{"three", url(module)}, {"three/core", url(v.three_core)},
                  {"three/addons/OrbitControls.js", url(v.orbit)}};
  return m.dump();
}

// An arbour run's paths.csv as segments: add(owner, a, b, step_a, step_b, type, order) for
// each. A neuron's k-th row is its SWC sample k + 2, and each row names the sample it hangs
// on (parent_sample; 1, the soma, draws no segment), which comes before it: a cone's
// previous point, or the branch point a cone starts from. Above kMaxPathPoints rows, every
// k-th row of a neuron is kept, and every cone's first and last (the page says so); a row
// left out passes its segment on to the next kept row below it.
template <class Add>
void add_arbour_segments(const Csv& paths, std::size_t n, std::vector<std::string>& notes, Add&& add) {
  const int c_id = paths.col("id"), c_cone = paths.col("cone"), c_type = paths.col("type"),
            c_order = paths.col("order"), c_step = paths.col("step"), c_x = paths.col("x"),
            c_parent = paths.col("parent_sample");
  if (std::min({c_id, c_type, c_order, c_step, c_x, c_parent}) < 0 || c_x + 2 >= static_cast<int>(paths.header.size()))
    paths.refuse(0, "an arbour paths.csv has the columns id,cone,parent,type,order,step,x,y,z,parent_sample");
  const std::size_t stride = (paths.rows.size() + kMaxPathPoints - 1) / kMaxPathPoints;
  if (stride > 1)
    notes.push_back(fmt::format("paths thinned: {} points, every {}th point kept (and each cone's first and last)",
                                paths.rows.size(), stride));
  struct Drawn {
    float p[3];
    float step;
  };
  std::vector<Drawn> drawn;        // this neuron's samples (index: sample id - 2) as drawn
  std::vector<std::int64_t> from;  // the kept sample each sample's segments start from (-1: the soma)
  long long neuron = -1;
  std::size_t first_row = 0;
  auto cell = [&](std::size_t k, int c) -> const std::string& { return paths.rows[k][static_cast<std::size_t>(c)]; };
  for (std::size_t k = 0; k < paths.rows.size(); ++k) {
    const long long id = paths.integer(k, c_id, 0, static_cast<long long>(n) - 1);
    if (id != neuron) drawn.clear(), from.clear(), neuron = id, first_row = k;
    const long long sample = static_cast<long long>(k - first_row) + 2;
    const long long parent = paths.integer(k, c_parent, 1, 4294967295LL);
    if (parent >= sample) paths.refuse(k, fmt::format("sample {} is listed before its parent sample {}", sample, parent));
    const Drawn here{{static_cast<float>(paths.number(k, c_x)), static_cast<float>(paths.number(k, c_x + 1)),
                      static_cast<float>(paths.number(k, c_x + 2))},
                     static_cast<float>(paths.integer(k, c_step, 0, 4294967295LL))};
    const auto type = static_cast<std::uint8_t>(paths.integer(k, c_type, 2, 3));
    const auto order = static_cast<std::uint8_t>(paths.integer(k, c_order, 0, 255));
    const bool cone_first = k == first_row || cell(k - 1, c_cone) != cell(k, c_cone);
    const bool cone_last = k + 1 == paths.rows.size() || cell(k + 1, c_id) != cell(k, c_id) ||
                           cell(k + 1, c_cone) != cell(k, c_cone);
    const std::int64_t start = parent == 1 ? -1 : from[static_cast<std::size_t>(parent - 2)];
    drawn.push_back(here);
    if ((k - first_row) % stride != 0 && !cone_first && !cone_last) {
      from.push_back(start);  // left out: its children draw from where it would have
      continue;
    }
    if (start >= 0) {
      const Drawn& a = drawn[static_cast<std::size_t>(start)];
      add(static_cast<std::uint32_t>(id), a.p, here.p, a.step, here.step, type, order);
    }
    from.push_back(sample - 2);
  }
}

}  // namespace

int cmd_view(const std::string& dir_name) {
  const fs::path dir(dir_name);
  if (!fs::is_directory(dir))
    throw InputError(fmt::format("view: {} is not a directory (give the --out directory of a run)", dir_name));
  // Only a whole run, and only the files its manifest lists: never a stale file beside it.
  const json manifest = require_whole_run(dir, "view");
  auto listed = [&](const char* name) { return manifest["files"].contains(name); };
  // The columns a run writes in each file the viewer reads (the fewest it indexes).
  auto load_listed = [&](const char* name, Csv& out, std::size_t columns) {
    return listed(name) && load_csv(dir / name, out, columns);
  };
  const ViewerFiles files = viewer_files();

  json meta;
  std::vector<std::string> missing, notes;
  Csv bfs, paths, sources, particles;
  // A run writes finite positions, known statuses and targets that are neuron ids (or
  // -1); anything else is not a run's data, and is refused rather than drawn.
  NeuronRows rows;
  if (listed("neurons.csv"))
    rows = read_neurons_csv(read_text(dir / "neurons.csv"), fmt::format("view: {}", (dir / "neurons.csv").string()));
  else
    missing.push_back("neurons.csv (no neurons to show)");
  const std::size_t n = rows.size();
  std::vector<float> soma(3 * n), tip(3 * n), length(n);
  std::vector<std::uint8_t> status(n);
  std::vector<std::uint32_t> steps(n);
  std::vector<std::int32_t> target(n);
  double extent = 1, soma_radius = 0.25;
  std::uint32_t steps_run = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const core::Vec3 s = rows.soma[i], t = rows.tip[i];
    soma[3 * i] = static_cast<float>(s.x), soma[3 * i + 1] = static_cast<float>(s.y), soma[3 * i + 2] = static_cast<float>(s.z);
    tip[3 * i] = static_cast<float>(t.x), tip[3 * i + 1] = static_cast<float>(t.y), tip[3 * i + 2] = static_cast<float>(t.z);
    soma_radius = rows.soma_radius[i];
    status[i] = static_cast<std::uint8_t>(rows.status[i]);
    length[i] = static_cast<float>(rows.length[i]);
    steps[i] = rows.steps[i];
    target[i] = rows.target[i] == core::kNoNeuron ? -1 : static_cast<std::int32_t>(rows.target[i]);
    steps_run = std::max(steps_run, steps[i]);
    extent = std::max(extent, std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z));
  }
  json data;
  data["soma"] = b64(soma);
  data["status"] = b64(status);
  data["steps"] = b64(steps);
  data["target"] = b64(target);
  data["length"] = b64(length);
  if (n == 0) throw InputError(fmt::format("view: {} holds a run of no neurons: nothing to draw", dir_name));
  if (!listed("connections.csv")) missing.push_back("connections.csv");
  if (load_listed("bfs.csv", bfs, 1)) {
    for (const char* col : {"level", "component"}) {
      const int c = bfs.col(col);
      if (c < 0) continue;
      std::vector<std::int32_t> v(n, -1);
      for (std::size_t k = 0; k < bfs.rows.size(); ++k)
        v[static_cast<std::size_t>(bfs.integer(k, 0, 0, static_cast<long long>(n) - 1))] =
            static_cast<std::int32_t>(bfs.integer(k, c, -1, static_cast<long long>(n)));
      data[col] = b64(v);
    }
  } else {
    missing.push_back("bfs.csv (no BFS levels or components to colour by)");
  }

  // Axon segments: from paths.csv when present (thinned to every k-th step if needed),
  // else one straight segment from the soma to the tip. Each vertex carries the step at
  // which the axon reached it; the shader hides fragments beyond the slider's time, so a
  // segment grows continuously (one segment per axon is enough for a straight axon). An
  // arbour run's paths.csv (id,cone,parent,type,order,step,x,y,z,parent_sample) gives every
  // point and the SWC sample it hangs on: each segment is drawn from there, and carries its
  // neurite type and centrifugal order, to colour by.
  std::vector<float> seg_pos, seg_step;
  std::vector<std::uint32_t> seg_owner;
  std::vector<std::uint8_t> seg_type, seg_order;
  auto add_segment = [&](std::uint32_t owner, const float* a, const float* b, float step_a, float step_b) {
    seg_pos.insert(seg_pos.end(), a, a + 3);
    seg_pos.insert(seg_pos.end(), b, b + 3);
    seg_step.push_back(step_a);
    seg_step.push_back(step_b);
    seg_owner.push_back(owner);
  };
  const bool arbours = load_listed("paths.csv", paths, 5) && paths.col("cone") >= 0;
  if (arbours) {
    add_arbour_segments(paths, n, notes, [&](std::uint32_t owner, const float* a, const float* b, float step_a,
                                             float step_b, std::uint8_t type, std::uint8_t order) {
      add_segment(owner, a, b, step_a, step_b);
      seg_type.push_back(type);
      seg_order.push_back(order);
    });
  } else if (!paths.rows.empty()) {
    const std::size_t stride = (paths.rows.size() + kMaxPathPoints - 1) / kMaxPathPoints;
    if (stride > 1)
      notes.push_back(fmt::format("paths thinned: {} points, every {}th step kept (and each axon's last)",
                                  paths.rows.size(), stride));
    float prev[3] = {0, 0, 0};
    float prev_step = 0;
    long prev_id = -1;
    for (std::size_t k = 0; k < paths.rows.size(); ++k) {
      const long id = static_cast<long>(paths.integer(k, 0, 0, static_cast<long long>(n) - 1));
      const auto step = static_cast<std::uint32_t>(paths.integer(k, 1, 0, 4294967295LL));
      const float p[3] = {static_cast<float>(paths.number(k, 2)), static_cast<float>(paths.number(k, 3)),
                          static_cast<float>(paths.number(k, 4))};
      const bool last = k + 1 == paths.rows.size() || paths.rows[k + 1][0] != paths.rows[k][0];
      if (id != prev_id) {
        std::copy(p, p + 3, prev);
        prev_step = static_cast<float>(step);
        prev_id = id;
        continue;
      }
      if (step % stride != 0 && !last) continue;
      add_segment(static_cast<std::uint32_t>(id), prev, p, prev_step, static_cast<float>(step));
      std::copy(p, p + 3, prev);
      prev_step = static_cast<float>(step);
    }
  } else {
    notes.push_back("no paths.csv (run with output.paths): axons drawn straight from soma to tip");
    for (std::size_t i = 0; i < n; ++i)
      add_segment(static_cast<std::uint32_t>(i), &soma[3 * i], &tip[3 * i], 0.0f, static_cast<float>(steps[i]));
  }
  if (arbours) {
    data["paths_type"] = b64(seg_type);
    data["paths_order"] = b64(seg_order);
    meta["arbours"] = true;
  }
  data["paths"] = {{"points", b64(seg_pos)}, {"step", b64(seg_step)}, {"owner", b64(seg_owner)}};

  json src = json::array();
  if (load_listed("sources.csv", sources, 5))
    for (std::size_t k = 0; k < sources.rows.size(); ++k)
      src.push_back({{"kind", printable(sources.rows[k][1])},
                     {"x", sources.number(k, 2)},
                     {"y", sources.number(k, 3)},
                     {"z", sources.number(k, 4)}});
  data["sources"] = src;

  json frames = json::array();
  if (load_listed("particles.csv", particles, 5)) {
    std::size_t start = 0;
    while (start < particles.rows.size()) {
      std::size_t end = start;
      const std::string step = particles.rows[start][0];
      while (end < particles.rows.size() && particles.rows[end][0] == step) ++end;
      const std::size_t count = end - start, stride = (count + kMaxFrameParticles - 1) / kMaxFrameParticles;
      if (stride > 1)
        notes.push_back(fmt::format("particle frame at step {}: {} particles, every {}th shown", step, count, stride));
      std::vector<float> pos;
      std::vector<std::uint8_t> cue;
      for (std::size_t k = start; k < end; k += stride) {
        for (int c = 2; c < 5; ++c) pos.push_back(static_cast<float>(particles.number(k, c)));
        cue.push_back(static_cast<std::uint8_t>(particles.integer(k, 1, 0, 255)));
      }
      frames.push_back({{"step", particles.integer(start, 0, 0, 4294967295LL)}, {"pos", b64(pos)}, {"cue", b64(cue)}});
      start = end;
    }
  }
  data["frames"] = frames;

  std::string title = fmt::format("axonguide: {}", fs::weakly_canonical(dir).filename().string());
  try {
    const json& m = manifest;
    steps_run = std::max<std::uint32_t>(steps_run, m.at("summary").at("steps_run").get<std::uint32_t>());
    title = fmt::format("axonguide: {} neurons, {} guidance, seed {}", m.at("summary").at("neurons").get<std::size_t>(),
                        m.at("scene").at("guidance").at("model").get<std::string>(), m.at("seed").get<std::uint64_t>());
    if (arbours) title += ", arbours";
  } catch (const std::exception&) {
    notes.push_back("the manifest has no run summary");
  }
  meta["neurons"] = n;
  meta["steps_run"] = steps_run;
  meta["extent"] = extent + soma_radius;
  meta["soma_radius"] = soma_radius;
  meta["missing"] = missing;
  meta["notes"] = notes;
  meta["title"] = title;
  data["meta"] = meta;

  std::string page = files.page;
  auto fill = [&](const std::string& key, const std::string& value) {
    const std::size_t p = page.find(key);
    if (p != std::string::npos) page.replace(p, key.size(), value);
  };
  std::string data_text = data.dump();
  // Inside <script>, "</" must not appear; JSON allows the escaped slash.
  for (std::size_t p = 0; (p = data_text.find("</", p)) != std::string::npos; p += 3) data_text.replace(p, 2, "<\\/");
  std::string notes_html;
  auto escape = [](std::string t) {
    std::string o;
    for (char c : t) o += c == '<' ? std::string("&lt;") : c == '>' ? std::string("&gt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
    return o;
  };
  for (const auto& m : missing) notes_html += "<div>missing: " + escape(m) + "</div>";
  for (const auto& note : notes) notes_html += "<div>" + escape(note) + "</div>";
  fill("{{NOTES}}", notes_html);
  fill("{{TITLE}}", title);
  fill("{{CSS}}", files.css);
  fill("{{IMPORTMAP}}", import_map(files));
  fill("{{VIEWJS}}", files.view_js);
  fill("{{DATA}}", data_text);
  AtomicFile f(dir, "view.html");
  f.write(page);
  f.commit();
  for (const auto& m : missing) std::fprintf(stderr, "axonguide: view: missing %s\n", m.c_str());
  for (const auto& note : notes) std::fprintf(stderr, "axonguide: view: %s\n", note.c_str());
  fmt::print("wrote {} ({:.1f} MiB): open it in a browser\n", (dir / "view.html").string(),
             static_cast<double>(page.size()) / 1048576.0);
  return kExitOk;
}

int cmd_plot(const std::string& dir_name) {
  const fs::path dir(dir_name);
  if (!fs::is_directory(dir)) throw InputError(fmt::format("plot: {} is not a directory", dir_name));
  const std::string& python = validate::plotting_python();
  if (python.empty()) throw RunError("plot: no python3 with matplotlib (install Debian's python3-matplotlib)");
  // The helper compiled in (or AXG_VIEWER_DIR's), handed to Python on its standard input.
  const char* viewer_env = std::getenv("AXG_VIEWER_DIR");
  const std::string source = viewer_env && *viewer_env ? read_text(fs::path(viewer_env) / "plot_run.py")
                                                       : std::string(assets::plot_run_py());
  const std::string script = "plot_run.py";
  require_whole_run(dir, "plot");
  // The helper prints one line and exits 2 (data) or 3 (machine) on every failure it can
  // catch; anything else (a crash, a signal, no interpreter) is reported here as one line.
  // Its messages go to this process's standard error, as they come.
  const int rc = validate::run_program({python, "-", dir.string()}, {}, &source);
  if (rc == -1) throw RunError(fmt::format("plot: cannot start {}", python));
  if (WIFSIGNALED(rc)) throw RunError(fmt::format("plot: {} was killed by signal {}", script, WTERMSIG(rc)));
  const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : kExitCannotRun;
  if (code == kExitOk || code == kExitBadInput || code == kExitCannotRun) return code;
  throw RunError(fmt::format("plot: {} failed (exit status {})", script, code));
}

}  // namespace axg::app
