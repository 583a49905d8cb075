// Morphometry of SWC morphologies (docs/methods.md §13): the reader with its checks, the
// segment statistics in the conventions of Ramakers' culture data, the population rows and
// the Sholl profile.
#include "axonguide/morphology/morphometry.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"

namespace axg::morphology {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad(const std::string& origin, std::size_t line, const std::string& what) {
  throw InputError(fmt::format("morphometry: {}:{}: {}", origin, line, what));
}

template <class T>
bool parse_number(std::string_view s, T& out) {
  const char* end = s.data() + s.size();
  if constexpr (std::is_floating_point_v<T>) {
    // from_chars rejects a leading '+', which SWC writers sometimes emit.
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto [p, ec] = std::from_chars(s.data(), end, out);
    return ec == std::errc() && p == end && std::isfinite(out);
  } else {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto [p, ec] = std::from_chars(s.data(), end, out);
    return ec == std::errc() && p == end;
  }
}

}  // namespace

Morphology parse_swc(const std::string& text, const std::string& origin) {
  Morphology m;
  m.name = fs::path(origin).stem().string();
  std::vector<std::size_t> lines;  // each sample's line in the file
  std::unordered_map<std::int64_t, std::size_t> index;
  std::istringstream in(text);
  std::string line;
  std::size_t number = 0;
  static const char* kField[7] = {"id", "type", "x", "y", "z", "radius", "parent"};
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::vector<std::string_view> f;
    std::string_view rest(line);
    while (true) {
      const std::size_t a = rest.find_first_not_of(" \t");
      if (a == std::string_view::npos) break;
      const std::size_t b = rest.find_first_of(" \t", a);
      f.push_back(rest.substr(a, b == std::string_view::npos ? std::string_view::npos : b - a));
      if (b == std::string_view::npos) break;
      rest = rest.substr(b);
    }
    if (f.size() != 7)
      bad(origin, number, fmt::format("{} fields; an SWC sample has 7 (id type x y z radius parent)", f.size()));
    Sample s{};
    double* reals[4] = {&s.x, &s.y, &s.z, &s.radius};
    for (int k = 0; k < 7; ++k) {
      bool ok = true;
      if (k == 0) ok = parse_number(f[0], s.id);
      else if (k == 1) ok = parse_number(f[1], s.type);
      else if (k == 6) ok = parse_number(f[6], s.parent);
      else ok = parse_number(f[k], *reals[k - 2]);
      if (!ok) bad(origin, number, fmt::format("field {} ({}) = \"{}\" is not a {}", k + 1, kField[k], f[k],
                                               (k == 0 || k == 1 || k == 6) ? "whole number" : "finite number"));
    }
    if (s.parent < 0 && s.parent != -1)
      bad(origin, number, fmt::format("parent {}: -1 (a root) or the id of another sample", s.parent));
    if (!index.emplace(s.id, m.samples.size()).second)
      bad(origin, number, fmt::format("id {} is given twice (first on line {})", s.id, lines[index.at(s.id)]));
    m.samples.push_back(s);
    lines.push_back(number);
  }
  if (m.samples.empty()) bad(origin, number, "no samples");
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    const Sample& s = m.samples[i];
    if (s.parent == -1) continue;
    const auto it = index.find(s.parent);
    if (it == index.end()) bad(origin, lines[i], fmt::format("sample {}: its parent {} is not in the file", s.id, s.parent));
    if (it->second < i) continue;
    // The parent comes at or after its child: a cycle when following parents returns here.
    std::size_t at = i;
    bool cycle = false;
    for (std::size_t hops = 0; hops <= m.samples.size(); ++hops) {
      const std::int64_t p = m.samples[at].parent;
      if (p == -1) break;
      const auto next = index.find(p);
      if (next == index.end()) break;
      at = next->second;
      if (at == i) {
        cycle = true;
        break;
      }
    }
    if (cycle) bad(origin, lines[i], fmt::format("sample {}: its parents lead back to it (a cycle)", s.id));
    bad(origin, lines[i], fmt::format("sample {}: its parent {} comes after it (line {}); SWC lists parents first",
                                      s.id, s.parent, lines[it->second]));
  }
  // Parents before children: store parents as indices from here on.
  for (std::size_t i = 0; i < m.samples.size(); ++i)
    if (m.samples[i].parent != -1) m.samples[i].parent = static_cast<std::int64_t>(index.at(m.samples[i].parent));
  return m;
}

Morphology read_swc(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("morphometry: cannot read {}", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  Morphology m = parse_swc(ss.str(), path.string());
  m.name = path.stem().string();
  return m;
}

namespace {

double piece(const Sample& a, const Sample& b, Projection p) {
  const double dx = a.x - b.x, dy = a.y - b.y, dz = p == Projection::kXY ? 0.0 : a.z - b.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

bool is_dendrite(int type) { return type == 3 || type == 4; }

// Adds the segments of the subtree under `stem` (its first sample) to `st`.
void add_subtree(const Morphology& m, const std::vector<std::vector<std::size_t>>& children, std::size_t stem,
                 Projection p, NeuriteStats& st, double& terminal_sum, double& intermediate_sum, int& intermediate_n) {
  // (sample, the length of its segment up to this sample)
  std::vector<std::pair<std::size_t, double>> stack{{stem, 0.0}};
  while (!stack.empty()) {
    auto [at, length] = stack.back();
    stack.pop_back();
    while (children[at].size() == 1) {
      const std::size_t c = children[at][0];
      const double d = piece(m.samples[c], m.samples[at], p);
      length += d;
      st.total_length += d;
      at = c;
    }
    if (children[at].empty()) {
      ++st.terminal_segments;
      terminal_sum += length;
      continue;
    }
    ++st.branch_points;
    intermediate_sum += length;
    ++intermediate_n;
    for (auto it = children[at].rbegin(); it != children[at].rend(); ++it) {
      const double d = piece(m.samples[*it], m.samples[at], p);
      st.total_length += d;
      stack.emplace_back(*it, d);
    }
  }
}

void finish(NeuriteStats& st, double terminal_sum, double intermediate_sum, int intermediate_n) {
  st.mean_terminal_segment_length = st.terminal_segments ? terminal_sum / st.terminal_segments : 0.0;
  st.mean_intermediate_segment_length = intermediate_n ? intermediate_sum / intermediate_n : 0.0;
}

std::vector<std::vector<std::size_t>> children_of(const Morphology& m) {
  std::vector<std::vector<std::size_t>> ch(m.samples.size());
  for (std::size_t i = 0; i < m.samples.size(); ++i)
    if (m.samples[i].parent >= 0) ch[static_cast<std::size_t>(m.samples[i].parent)].push_back(i);
  return ch;
}

// A neurite's first sample: not a soma sample, and its parent is a soma sample or none.
bool is_stem(const Morphology& m, std::size_t i) {
  const Sample& s = m.samples[i];
  return s.type != 1 && (s.parent < 0 || m.samples[static_cast<std::size_t>(s.parent)].type == 1);
}

}  // namespace

NeuronStats measure(const Morphology& m, Projection p) {
  NeuronStats out;
  out.name = m.name;
  const auto children = children_of(m);
  double a_term = 0, a_inter = 0;
  int a_inter_n = 0;
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    if (!is_stem(m, i)) continue;
    if (m.samples[i].type == 2) {
      out.has_axon = true;
      add_subtree(m, children, i, p, out.axon, a_term, a_inter, a_inter_n);
    } else if (is_dendrite(m.samples[i].type)) {
      NeuriteStats d;
      double t = 0, in = 0;
      int n = 0;
      add_subtree(m, children, i, p, d, t, in, n);
      finish(d, t, in, n);
      out.dendrites.push_back(d);
    }
  }
  finish(out.axon, a_term, a_inter, a_inter_n);
  return out;
}

const std::vector<std::string>& statistic_names() {
  static const std::vector<std::string> names{"total_axon_length",
                                              "branch_points_per_axon",
                                              "terminal_segments_per_axon",
                                              "axons_mean_terminal_segment_length",
                                              "axons_mean_intermediate_segment_length",
                                              "number_of_dendrites_per_neuron",
                                              "total_dendrite_length",
                                              "branch_points_per_dendrite",
                                              "terminal_segments_per_dendrite",
                                              "dendrites_mean_terminal_segment_length",
                                              "dendrites_mean_intermediate_segment_length"};
  return names;
}

namespace {

Row summarise(const std::string& name, const std::vector<double>& x) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Row r{name, x.size(), nan, nan, nan};
  if (x.empty()) return r;
  double sum = 0;
  for (double v : x) sum += v;  // in neuron (file) order
  r.mean = sum / static_cast<double>(x.size());
  if (x.size() < 2) return r;
  double ss = 0;
  for (double v : x) ss += (v - r.mean) * (v - r.mean);
  r.sd = std::sqrt(ss / static_cast<double>(x.size() - 1));
  r.se = r.sd / std::sqrt(static_cast<double>(x.size()));
  return r;
}

}  // namespace

std::vector<Row> population(const std::vector<NeuronStats>& neurons) {
  std::vector<double> v[11];
  for (const NeuronStats& n : neurons) {
    if (n.has_axon) {
      v[0].push_back(n.axon.total_length);
      v[1].push_back(n.axon.branch_points);
      v[2].push_back(n.axon.terminal_segments);
      v[3].push_back(n.axon.mean_terminal_segment_length);
      v[4].push_back(n.axon.mean_intermediate_segment_length);
    }
    v[5].push_back(static_cast<double>(n.dendrites.size()));
    for (const NeuriteStats& d : n.dendrites) {
      v[6].push_back(d.total_length);
      v[7].push_back(d.branch_points);
      v[8].push_back(d.terminal_segments);
      v[9].push_back(d.mean_terminal_segment_length);
      v[10].push_back(d.mean_intermediate_segment_length);
    }
  }
  std::vector<Row> rows;
  for (std::size_t k = 0; k < 11; ++k) rows.push_back(summarise(statistic_names()[k], v[k]));
  return rows;
}

std::vector<int> sholl(const Morphology& m, int type_set, double step, Projection p) {
  if (!(step > 0)) throw InputError(fmt::format("morphometry: Sholl step {}: must be > 0", step));
  auto in_set = [&](int type) { return type_set == 2 ? type == 2 : is_dendrite(type); };
  // The centre: the first soma sample, else the first sample.
  std::size_t c = 0;
  for (std::size_t i = 0; i < m.samples.size(); ++i)
    if (m.samples[i].type == 1) {
      c = i;
      break;
    }
  // Each sample's group: the type of the stem it descends from.
  std::vector<int> group(m.samples.size(), 0);
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    if (m.samples[i].type == 1) continue;
    group[i] = is_stem(m, i) ? m.samples[i].type : group[static_cast<std::size_t>(m.samples[i].parent)];
  }
  double far = 0;
  for (std::size_t i = 0; i < m.samples.size(); ++i)
    if (group[i] != 0 && in_set(group[i])) far = std::max(far, piece(m.samples[i], m.samples[c], p));
  const std::size_t radii = static_cast<std::size_t>(std::ceil(far / step));
  std::vector<int> crossings(radii, 0);
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    if (group[i] == 0 || !in_set(group[i]) || is_stem(m, i)) continue;
    const double a = piece(m.samples[i], m.samples[c], p);
    const double b = piece(m.samples[static_cast<std::size_t>(m.samples[i].parent)], m.samples[c], p);
    for (std::size_t k = 0; k < radii; ++k) {
      const double r = step * static_cast<double>(k + 1);
      if ((a <= r) != (b <= r)) ++crossings[k];
    }
  }
  return crossings;
}

std::vector<Morphology> read_folder(const fs::path& dir) {
  fs::path where = dir;
  if (fs::is_directory(dir / "morphologies")) where = dir / "morphologies";
  if (!fs::is_directory(where)) throw InputError(fmt::format("morphometry: {} is not a folder", dir.string()));
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(where))
    if (e.is_regular_file() && e.path().extension() == ".swc") files.push_back(e.path());
  if (files.empty())
    throw InputError(fmt::format("morphometry: no .swc file in {} (a run writes them with output.swc: true)",
                                 where.string()));
  // Numeric stems in numeric order first (a run's 0.swc, 1.swc, ...), then the rest by name.
  auto numeric = [](const fs::path& f, std::uint64_t& v) {
    const std::string s = f.stem().string();
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && p == s.data() + s.size();
  };
  std::sort(files.begin(), files.end(), [&](const fs::path& a, const fs::path& b) {
    std::uint64_t x = 0, y = 0;
    const bool na = numeric(a, x), nb = numeric(b, y);
    if (na != nb) return na;
    if (na && x != y) return x < y;
    return a.filename().string() < b.filename().string();
  });
  std::vector<Morphology> out;
  for (const auto& f : files) out.push_back(read_swc(f));
  return out;
}

}  // namespace axg::morphology
