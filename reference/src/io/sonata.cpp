// SONATA output (docs/guide.md §1.2) through the HDF5 C API. Each HDF5 file is written
// under a temporary name, closed, synced and renamed, so it appears under its name only
// when whole, and hashed from disk (HDF5 writes out of order).
//
// Byte determinism: every group and dataset is created with object time tracking off,
// the format is pinned (libver bounds earliest..1.8: superblock 0, version-1 object
// headers, symbol-table groups, whose links are kept sorted by name), the layout is
// contiguous without filters, and the calls are the same for a given run whatever the
// thread count. Strings are fixed-length, so nothing goes to a global heap.
#include "axonguide/io/sonata.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "axonguide/io/canonical_nan.hpp"
#include "axonguide/morphology/sections.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/swc.hpp"

// Sweeps write their members' SONATA files on several threads at once: the HDF5 library must
// be a thread-safe build (Debian's is).
#if !defined(H5_HAVE_THREADSAFE) || !H5_HAVE_THREADSAFE
#error "SONATA output needs a thread-safe HDF5 build (H5_HAVE_THREADSAFE): sweeps write from several threads"
#endif

namespace axg {

namespace fs = std::filesystem;

namespace {

constexpr const char* kNodePopulation = "axonguide";
constexpr const char* kEdgePopulation = "axonguide_to_axonguide";
// SONATA's root attributes: the spec version the file follows, and its magic number.
constexpr std::uint32_t kSonataVersion[2] = {0, 1};
constexpr std::uint32_t kSonataMagic = 0x0A7A;
// The status enumeration's names, in core::AxonStatus order (name_of).
constexpr std::array<const char*, 4> kStatusNames = {"growing", "connected", "exited", "max_steps"};

// An HDF5 call's failure (write_sonata adds the file's name; the writer's own I/O errors,
// the fsync and the rename, name it already).
struct Hdf5Error : RunError {
  using RunError::RunError;
};

[[noreturn]] void fail(const char* what) { throw Hdf5Error(fmt::format("SONATA output: HDF5 {} failed", what)); }

// Closes that fail in a Handle's destructor (a dataset whose cached rows cannot be written,
// say), counted on the thread that writes the file, so that H5Output::commit() refuses the
// file: a destructor must not throw. A file is written on one thread (sweeps write several
// at once, each on its own).
thread_local std::uint64_t t_failed_closes = 0;

// HDF5 1.10.8 (Debian 12's) frees a file whose close failed (a full disk, say) but keeps its
// identifier, and its exit-time cleanup then closes it again and crashes the process
// (HDFFV-11052, fixed in HDF5 1.14.1): a failed SONATA write would end in SIGSEGV, not in
// its RunError's exit code. This writer closes every file it opens itself, so that cleanup
// has nothing to do: the first file it creates switches it off, which takes effect when the
// library is not started yet (the command's case; a process that used HDF5 before, through
// h5py say, keeps its cleanup, and a program that never writes SONATA is not touched).
void no_exit_cleanup() {
  [[maybe_unused]] static const herr_t once = H5dont_atexit();
}

void ok(herr_t status, const char* what) {
  if (status < 0) fail(what);
}

// One HDF5 identifier, closed by its own close function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const char* what) : id_(id), close_(close) {
    if (id_ < 0) fail(what);
  }
  ~Handle() {
    if (id_ >= 0 && close_(id_) < 0) ++t_failed_closes;
  }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle& operator=(Handle&&) = delete;
  operator hid_t() const { return id_; }
  herr_t close() {
    const herr_t status = id_ >= 0 ? close_(id_) : 0;
    id_ = -1;
    return status;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

Handle property_list(hid_t cls) { return Handle(H5Pcreate(cls), H5Pclose, "H5Pcreate"); }

// File and memory types of the element types written.
template <class T>
struct H5Of;
template <>
struct H5Of<std::uint8_t> {
  static hid_t file() { return H5T_STD_U8LE; }
  static hid_t mem() { return H5T_NATIVE_UINT8; }
};
template <>
struct H5Of<std::uint32_t> {
  static hid_t file() { return H5T_STD_U32LE; }
  static hid_t mem() { return H5T_NATIVE_UINT32; }
};
template <>
struct H5Of<std::int32_t> {
  static hid_t file() { return H5T_STD_I32LE; }
  static hid_t mem() { return H5T_NATIVE_INT32; }
};
template <>
struct H5Of<std::uint64_t> {
  static hid_t file() { return H5T_STD_U64LE; }
  static hid_t mem() { return H5T_NATIVE_UINT64; }
};
template <>
struct H5Of<double> {
  static hid_t file() { return H5T_IEEE_F64LE; }
  static hid_t mem() { return H5T_NATIVE_DOUBLE; }
};

// A fixed-length, null-padded UTF-8 string type of `size` bytes.
Handle string_type(std::size_t size) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose, "H5Tcopy");
  ok(H5Tset_size(t, size == 0 ? 1 : size), "H5Tset_size");
  ok(H5Tset_strpad(t, H5T_STR_NULLPAD), "H5Tset_strpad");
  ok(H5Tset_cset(t, H5T_CSET_UTF8), "H5Tset_cset");
  return t;
}

void string_attribute(hid_t object, const char* name, const std::string& value) {
  Handle type = string_type(value.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "H5Screate");
  Handle attr(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, "H5Acreate2");
  std::string padded = value;
  padded.resize(value.empty() ? 1 : value.size(), '\0');
  ok(H5Awrite(attr, type, padded.data()), "H5Awrite");
}

template <class T>
void scalar_attribute(hid_t object, const char* name, const T* values, hsize_t count) {
  Handle space(count == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr), H5Sclose, "H5Screate");
  Handle attr(H5Acreate2(object, name, H5Of<T>::file(), space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "H5Acreate2");
  ok(H5Awrite(attr, H5Of<T>::mem(), values), "H5Awrite");
}

Handle group(hid_t parent, const char* name) {
  Handle gcpl = property_list(H5P_GROUP_CREATE);
  ok(H5Pset_obj_track_times(gcpl, 0), "H5Pset_obj_track_times");
  return Handle(H5Gcreate2(parent, name, H5P_DEFAULT, gcpl, H5P_DEFAULT), H5Gclose, "H5Gcreate2");
}

// A contiguous dataset of `dims` elements, never pre-filled, not yet written.
Handle empty_dataset(hid_t parent, const char* name, hid_t file_type, std::initializer_list<hsize_t> dims) {
  const std::vector<hsize_t> d(dims);
  Handle space(H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr), H5Sclose, "H5Screate_simple");
  Handle dcpl = property_list(H5P_DATASET_CREATE);
  ok(H5Pset_obj_track_times(dcpl, 0), "H5Pset_obj_track_times");
  ok(H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER), "H5Pset_fill_time");
  return Handle(H5Dcreate2(parent, name, file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose, "H5Dcreate2");
}

// A contiguous dataset of `dims` elements from `data` (row-major), never pre-filled.
Handle dataset(hid_t parent, const char* name, hid_t file_type, hid_t mem_type, const void* data,
               std::initializer_list<hsize_t> dims) {
  Handle set = empty_dataset(parent, name, file_type, dims);
  hsize_t total = 1;
  for (hsize_t x : dims) total *= x;
  if (total > 0) ok(H5Dwrite(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "H5Dwrite");
  return set;
}

// Rows [row, row + rows) of a 2-D dataset of `cols` columns (0: a 1-D dataset) from `data`,
// row-major. A dataset written a slab at a time has the bytes of one write: contiguous
// storage, allocated whole at the first write.
void write_rows(hid_t set, hid_t mem_type, hsize_t row, hsize_t rows, hsize_t cols, const void* data) {
  if (rows == 0) return;
  Handle file_space(H5Dget_space(set), H5Sclose, "H5Dget_space");
  const int rank = cols ? 2 : 1;
  const hsize_t start[2] = {row, 0}, count[2] = {rows, cols};
  ok(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr), "H5Sselect_hyperslab");
  Handle mem_space(H5Screate_simple(rank, count, nullptr), H5Sclose, "H5Screate_simple");
  ok(H5Dwrite(set, mem_type, mem_space, file_space, H5P_DEFAULT, data), "H5Dwrite");
}

// The rows of one slab: what the writer computes it holds a slab of, never a whole column.
constexpr std::size_t kSlab = std::size_t{1} << 16;

// A dataset of `count` rows written a slab at a time, never held whole: fill(begin, out,
// size) writes rows [begin, begin + size) to out, called for ascending begins. A Row is one
// element (cols 0: a 1-D dataset) or an array of `cols` of them.
template <class Row, class Fill>
Handle streamed_rows(hid_t parent, const char* name, hid_t file_type, hid_t mem_type, std::size_t count, hsize_t cols,
                     Fill&& fill) {
  Handle set = cols ? empty_dataset(parent, name, file_type, {count, cols})
                    : empty_dataset(parent, name, file_type, {count});
  std::vector<Row> slab(std::min(count, kSlab));
  for (std::size_t begin = 0; begin < count; begin += kSlab) {
    const std::size_t size = std::min(kSlab, count - begin);
    fill(begin, slab.data(), size);
    write_rows(set, mem_type, begin, size, cols, slab.data());
  }
  return set;
}

// A column of `count` elements, streamed_rows's 1-D case.
template <class T, class Fill>
Handle streamed_column(hid_t parent, const char* name, std::size_t count, Fill&& fill, const char* units = nullptr) {
  Handle set = streamed_rows<T>(parent, name, H5Of<T>::file(), H5Of<T>::mem(), count, 0, std::forward<Fill>(fill));
  if (units) string_attribute(set, "units", units);
  return set;
}

void fill_iota(std::size_t begin, std::uint64_t* out, std::size_t size) {
  std::iota(out, out + size, std::uint64_t{begin});
}
void fill_zeros(std::size_t, std::uint32_t* out, std::size_t size) { std::fill(out, out + size, 0u); }

template <class T>
Handle column(hid_t parent, const char* name, const std::vector<T>& values, const char* units = nullptr) {
  Handle set = dataset(parent, name, H5Of<T>::file(), H5Of<T>::mem(), values.data(), {values.size()});
  if (units) string_attribute(set, "units", units);
  return set;
}

void strings(hid_t parent, const char* name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& s : values) width = std::max(width, s.size());
  std::string packed(width * values.size(), '\0');
  for (std::size_t k = 0; k < values.size(); ++k) packed.replace(k * width, values[k].size(), values[k]);
  Handle type = string_type(width);
  dataset(parent, name, type, type, packed.data(), {values.size()});
}

// An HDF5 file written under a temporary name in `dir` (".NAME.tmp-PID", as AtomicFile
// names them) and renamed by commit(); removed if never committed.
class H5Output {
 public:
  H5Output(const fs::path& dir, const std::string& name)
      : name_(name), final_(dir / name), temp_(dir / fmt::format(".{}.tmp-{}", name, ::getpid())), file_(create()) {
    try {
      scalar_attribute(file_, "version", kSonataVersion, 2);
      scalar_attribute(file_, "magic", &kSonataMagic, 1);
    } catch (...) {  // no destructor runs after a constructor throws
      file_.close();
      std::error_code ec;
      fs::remove(temp_, ec);
      throw;
    }
  }
  ~H5Output() {
    if (committed_) return;
    file_.close();
    std::error_code ec;
    fs::remove(temp_, ec);
  }
  H5Output(const H5Output&) = delete;
  H5Output& operator=(const H5Output&) = delete;
  operator hid_t() const { return file_; }

  // Flushes, closes, syncs and renames the file into place. Every object in it must be
  // closed first (H5F_CLOSE_SEMI: H5Fclose fails otherwise, instead of leaving the file open
  // until the last object closes, after the rename), and none may have failed to close.
  void commit() {
    if (t_failed_closes != closes_before_) fail("closing an object");
    ok(H5Fflush(file_, H5F_SCOPE_LOCAL), "H5Fflush");
    if (file_.close() < 0) fail("H5Fclose");
    const int fd = ::open(temp_.c_str(), O_RDONLY);
    const bool synced = fd >= 0 && ::fsync(fd) == 0;
    const int err = errno;
    if (fd >= 0) ::close(fd);
    if (!synced) throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(err)));
    fault_point("output " + name_);
    std::error_code ec;
    fs::rename(temp_, final_, ec);
    if (ec) throw RunError(fmt::format("cannot rename {} to {}: {}", temp_.string(), final_.string(), ec.message()));
    committed_ = true;
  }

 private:
  std::string name_;
  fs::path final_, temp_;
  Handle file_;
  bool committed_ = false;
  std::uint64_t closes_before_ = t_failed_closes;

  Handle create() {
    no_exit_cleanup();  // before the first call that starts the library
    Handle fapl = property_list(H5P_FILE_ACCESS), fcpl = property_list(H5P_FILE_CREATE);
    ok(H5Pset_libver_bounds(fapl, H5F_LIBVER_EARLIEST, H5F_LIBVER_V18), "H5Pset_libver_bounds");
    ok(H5Pset_fclose_degree(fapl, H5F_CLOSE_SEMI), "H5Pset_fclose_degree");
#if H5_VERSION_GE(1, 10, 7)
    // The temporary is this process's own; no lock (which some file systems refuse).
    ok(H5Pset_file_locking(fapl, false, true), "H5Pset_file_locking");
#endif
    ok(H5Pset_obj_track_times(fcpl, 0), "H5Pset_obj_track_times");  // the root group
    return Handle(H5Fcreate(temp_.c_str(), H5F_ACC_TRUNC, fcpl, fapl), H5Fclose, "H5Fcreate");
  }
};

// Every column the writer computes is written a slab at a time (streamed_column), so that
// the writer holds about a slab beside the run's result, not a column.
void write_nodes(const RunResult& r, const fs::path& dir) {
  const std::size_t n = r.neurons.size();
  const double um = r.scene.units.micrometres();
  H5Output f(dir, "nodes.h5");
  {  // every object closed before the commit
    Handle nodes = group(f, "nodes");
    Handle pop = group(nodes, kNodePopulation);
    streamed_column<std::uint64_t>(pop, "node_id", n, fill_iota);
    streamed_column<std::uint64_t>(pop, "node_group_index", n, fill_iota);
    streamed_column<std::uint32_t>(pop, "node_type_id", n, fill_zeros);
    streamed_column<std::uint32_t>(pop, "node_group_id", n, fill_zeros);
    Handle g0 = group(pop, "0");
    constexpr double core::Vec3::*kAxes[] = {&core::Vec3::x, &core::Vec3::y, &core::Vec3::z};
    constexpr const char* kNames[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
      streamed_column<double>(
          g0, kNames[a], n,
          [&](std::size_t begin, double* out, std::size_t size) {
            for (std::size_t k = 0; k < size; ++k) out[k] = canonical(r.soma[begin + k].*kAxes[a] * um);
          },
          "um");
    const double soma_radius = canonical(r.scene.neurons.soma_radius * um);
    streamed_column<double>(
        g0, "soma_radius", n,
        [&](std::size_t, double* out, std::size_t size) { std::fill(out, out + size, soma_radius); }, "um");
    streamed_column<double>(
        g0, "axon_length", n,
        [&](std::size_t begin, double* out, std::size_t size) {
          for (std::size_t k = 0; k < size; ++k) out[k] = canonical(r.neurons.length[begin + k] * um);
        },
        "um");
    streamed_column<std::uint8_t>(g0, "status", n, [&](std::size_t begin, std::uint8_t* out, std::size_t size) {
      for (std::size_t k = 0; k < size; ++k) out[k] = static_cast<std::uint8_t>(r.neurons.status[begin + k]);
    });
    column(g0, "steps", r.neurons.steps);
    if (r.scene.arbours) {
      // Each node names its soma-centred morphology (network/morphologies/<id>.swc), which
      // SONATA clients place at the node's x, y, z: the name without its extension, as the
      // SONATA spec's "morphology" attribute has it.
      std::vector<std::string> names(n);
      for (std::size_t i = 0; i < n; ++i) names[i] = std::to_string(i);
      strings(g0, "morphology", names);
    }
    if (r.graph.bfs) column(g0, "bfs_level", r.graph.bfs->level);
    if (!r.graph.component.empty()) column(g0, "component", r.graph.component);
    {
      Handle library = group(g0, "@library");
      strings(library, "status", std::vector<std::string>(kStatusNames.begin(), kStatusNames.end()));
    }
  }
  f.commit();
}

// indices/<name>: the edges of each node as libsonata's index writer lays them out
// (edge_index.cpp): range_to_edge_id holds the maximal runs of equal node id in edge order,
// grouped by node (ascending) and in edge order within a node; node_id_to_ranges[v] is the
// half-open row range of v's runs, empty ([k, k]) for a node without edges. node_of(e) is
// edge e's node; the writer holds 4 B a node and 4 B a run, and writes both a slab at a time.
template <class NodeOf>
void edge_index(hid_t indices, const char* name, std::size_t m, NodeOf node_of, std::size_t nodes) {
  auto starts_run = [&](std::size_t e) { return e == 0 || node_of(e) != node_of(e - 1); };
  std::vector<std::uint32_t> first(nodes + 1, 0);  // first row of node v's runs (runs <= edges < 2^32)
  for (std::size_t e = 0; e < m; ++e)
    if (starts_run(e)) ++first[node_of(e) + 1];
  for (std::size_t v = 0; v < nodes; ++v) first[v + 1] += first[v];
  Handle g = group(indices, name);
  using Range = std::array<std::uint64_t, 2>;
  streamed_rows<Range>(g, "node_id_to_ranges", H5T_STD_U64LE, H5T_NATIVE_UINT64, nodes, 2,
                       [&](std::size_t begin, Range* out, std::size_t size) {
                         for (std::size_t k = 0; k < size; ++k) out[k] = {first[begin + k], first[begin + k + 1]};
                       });
  // The first edge of every run, at its row: runs in edge order, counted out by node.
  const std::size_t runs = first[nodes];
  std::vector<std::uint32_t> run_start(runs);
  for (std::size_t e = 0; e < m; ++e)
    if (starts_run(e)) run_start[first[node_of(e)]++] = static_cast<std::uint32_t>(e);
  first = std::vector<std::uint32_t>();  // freed before the rows are written
  streamed_rows<Range>(g, "range_to_edge_id", H5T_STD_U64LE, H5T_NATIVE_UINT64, runs, 2,
                       [&](std::size_t begin, Range* out, std::size_t size) {
                         for (std::size_t k = 0; k < size; ++k) {
                           const std::size_t start = run_start[begin + k];
                           std::size_t end = start + 1;
                           while (end < m && node_of(end) == node_of(start)) ++end;
                           out[k] = {start, end};
                         }
                       });
}

// A synapse scene's edges: one per realised synapse, in synapses.csv's order (by source),
// with SONATA's synapse attributes: the afferent (dendrite) and efferent (axon) section id
// and position as NEURON numbers the sections of the SWC it loads (morphology/sections.hpp),
// the two points (µm), and a delay from the axon's path length from the soma.
void write_synapse_edges(const RunResult& r, const fs::path& dir) {
  const double um = r.scene.units.micrometres();
  const double speed = r.scene.output.conduction_m_per_s();
  const network::Appositions& a = r.synapses;
  std::vector<std::uint32_t> kept;  // the realised synapses' rows
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a.realised[k]) kept.push_back(static_cast<std::uint32_t>(k));
  const std::size_t m = kept.size();
  // Each neuron's samples and sections, computed once, in parallel.
  const std::size_t n = r.arbours.size();
  std::vector<std::vector<morphology::ArbourSample>> samples(n);
  std::vector<morphology::Sections> sections(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    samples[i] = morphology::arbour_samples(r.arbours[i]);
    sections[i] = morphology::sections_of(samples[i], r.soma[i]);
  });
  struct Site {
    morphology::SectionPoint afferent, efferent;
    double path;  // the axon's path length from the soma to the synapse (length units)
  };
  std::vector<Site> site(m);
  tbb::parallel_for(std::size_t{0}, m, [&](std::size_t e) {
    const network::Contact& c = a.at[kept[e]];
    site[e].afferent = morphology::locate(sections[c.post], samples[c.post], c.post_sample, c.t);
    site[e].efferent = morphology::locate(sections[c.pre], samples[c.pre], c.pre_sample, c.s);
    const auto& sp = samples[c.pre];
    const std::size_t k = c.pre_sample - 2;
    const double seg = core::norm(sp[k].pos - sp[sp[k].parent - 2].pos);
    site[e].path = sections[c.pre].path[k] - (1.0 - c.s) * seg;
  });
  H5Output f(dir, "edges.h5");
  {  // every object closed before the commit
    Handle edges = group(f, "edges");
    Handle pop = group(edges, kEdgePopulation);
    auto ids = [&](const char* name, auto id) {
      Handle set = streamed_column<std::uint64_t>(pop, name, m, [&](std::size_t begin, std::uint64_t* out, std::size_t size) {
        for (std::size_t k = 0; k < size; ++k) out[k] = id(a.at[kept[begin + k]]);
      });
      string_attribute(set, "node_population", kNodePopulation);
    };
    ids("source_node_id", [](const network::Contact& c) { return c.pre; });
    ids("target_node_id", [](const network::Contact& c) { return c.post; });
    streamed_column<std::uint32_t>(pop, "edge_type_id", m, fill_zeros);
    streamed_column<std::uint32_t>(pop, "edge_group_id", m, fill_zeros);
    streamed_column<std::uint64_t>(pop, "edge_group_index", m, fill_iota);
    Handle g0 = group(pop, "0");
    auto u32 = [&](const char* name, auto value) {
      streamed_column<std::uint32_t>(g0, name, m, [&](std::size_t begin, std::uint32_t* out, std::size_t size) {
        for (std::size_t k = 0; k < size; ++k) out[k] = value(begin + k);
      });
    };
    auto f64 = [&](const char* name, auto value, const char* units) {
      return streamed_column<double>(
          g0, name, m,
          [&](std::size_t begin, double* out, std::size_t size) {
            for (std::size_t k = 0; k < size; ++k) out[k] = canonical(value(begin + k));
          },
          units);
    };
    u32("afferent_section_id", [&](std::size_t e) { return site[e].afferent.section; });
    f64("afferent_section_pos", [&](std::size_t e) { return site[e].afferent.pos; }, nullptr);
    u32("efferent_section_id", [&](std::size_t e) { return site[e].efferent.section; });
    f64("efferent_section_pos", [&](std::size_t e) { return site[e].efferent.pos; }, nullptr);
    f64("afferent_center_x", [&](std::size_t e) { return a.on_dendrite[kept[e]].x * um; }, "um");
    f64("afferent_center_y", [&](std::size_t e) { return a.on_dendrite[kept[e]].y * um; }, "um");
    f64("afferent_center_z", [&](std::size_t e) { return a.on_dendrite[kept[e]].z * um; }, "um");
    f64("efferent_center_x", [&](std::size_t e) { return a.on_axon[kept[e]].x * um; }, "um");
    f64("efferent_center_y", [&](std::size_t e) { return a.on_axon[kept[e]].y * um; }, "um");
    f64("efferent_center_z", [&](std::size_t e) { return a.on_axon[kept[e]].z * um; }, "um");
    f64("distance", [&](std::size_t e) { return a.at[kept[e]].distance * um; }, "um");
    u32("contacts", [&](std::size_t e) { return a.contacts[kept[e]]; });
    u32("step", [&](std::size_t e) { return a.at[kept[e]].step; });
    f64("axon_path_length", [&](std::size_t e) { return site[e].path * um; }, "um");
    {
      Handle set = f64("delay", [&](std::size_t e) { return site[e].path * um / (speed * 1000.0); }, "ms");
      scalar_attribute(set, "conduction_speed", &speed, 1);
      string_attribute(set, "conduction_speed_units", "m/s");
    }
    {
      Handle dynamics = group(g0, "dynamics_params");
      ok(H5Lcreate_hard(g0, "delay", dynamics, "delay", H5P_DEFAULT, H5P_DEFAULT), "H5Lcreate_hard");
    }
    Handle indices = group(pop, "indices");
    edge_index(indices, "source_to_target", m, [&](std::size_t e) { return a.at[kept[e]].pre; }, r.neurons.size());
    edge_index(indices, "target_to_source", m, [&](std::size_t e) { return a.at[kept[e]].post; }, r.neurons.size());
  }
  f.commit();
}

void write_edges(const RunResult& r, const fs::path& dir) {
  if (r.scene.synapses) return write_synapse_edges(r, dir);
  const auto& nr = r.neurons;
  const double um = r.scene.units.micrometres();
  const double speed = r.scene.output.conduction_m_per_s();  // m/s = mm/ms = 1000 µm/ms
  // The edges, in the order of their sources: source[e]; its target is nr.target[source[e]].
  std::vector<std::uint32_t> source;
  source.reserve(static_cast<std::size_t>(
      std::count_if(nr.target.begin(), nr.target.end(), [](std::uint32_t t) { return t != core::kNoNeuron; })));
  for (std::size_t i = 0; i < nr.size(); ++i)
    if (nr.target[i] != core::kNoNeuron) source.push_back(static_cast<std::uint32_t>(i));
  const std::size_t m = source.size();
  auto target_of = [&](std::size_t e) { return nr.target[source[e]]; };
  H5Output f(dir, "edges.h5");
  {  // every object closed before the commit
    Handle edges = group(f, "edges");
    Handle pop = group(edges, kEdgePopulation);
    {
      Handle set = streamed_column<std::uint64_t>(pop, "source_node_id", m,
                                                  [&](std::size_t begin, std::uint64_t* out, std::size_t size) {
                                                    for (std::size_t k = 0; k < size; ++k) out[k] = source[begin + k];
                                                  });
      string_attribute(set, "node_population", kNodePopulation);
    }
    {
      Handle set = streamed_column<std::uint64_t>(pop, "target_node_id", m,
                                                  [&](std::size_t begin, std::uint64_t* out, std::size_t size) {
                                                    for (std::size_t k = 0; k < size; ++k) out[k] = target_of(begin + k);
                                                  });
      string_attribute(set, "node_population", kNodePopulation);
    }
    streamed_column<std::uint32_t>(pop, "edge_type_id", m, fill_zeros);
    streamed_column<std::uint32_t>(pop, "edge_group_id", m, fill_zeros);
    streamed_column<std::uint64_t>(pop, "edge_group_index", m, fill_iota);
    Handle g0 = group(pop, "0");
    streamed_column<std::uint32_t>(g0, "step", m, [&](std::size_t begin, std::uint32_t* out, std::size_t size) {
      for (std::size_t k = 0; k < size; ++k) out[k] = nr.steps[source[begin + k]];
    });
    auto length_of = [&](std::size_t e) { return canonical(nr.length[source[e]] * um); };
    streamed_column<double>(
        g0, "length", m,
        [&](std::size_t begin, double* out, std::size_t size) {
          for (std::size_t k = 0; k < size; ++k) out[k] = length_of(begin + k);
        },
        "um");
    {
      Handle set = streamed_column<double>(
          g0, "delay", m,
          [&](std::size_t begin, double* out, std::size_t size) {
            for (std::size_t k = 0; k < size; ++k) out[k] = canonical(length_of(begin + k) / (speed * 1000.0));
          },
          "ms");
      scalar_attribute(set, "conduction_speed", &speed, 1);
      string_attribute(set, "conduction_speed_units", "m/s");
    }
    {
      // The same delays where PyNN's importer looks for per-edge synapse parameters: a
      // second (hard) link to the one dataset, not a copy.
      Handle dynamics = group(g0, "dynamics_params");
      ok(H5Lcreate_hard(g0, "delay", dynamics, "delay", H5P_DEFAULT, H5P_DEFAULT), "H5Lcreate_hard");
    }
    Handle indices = group(pop, "indices");
    edge_index(indices, "source_to_target", m, [&](std::size_t e) { return source[e]; }, nr.size());
    edge_index(indices, "target_to_source", m, target_of, nr.size());
  }
  f.commit();
}

// SONATA's CSV dialect: space-separated, a header row, UNIX line ends.
constexpr const char* kNodeTypes =
    "node_type_id population model_type model_template\n"
    "0 axonguide point_neuron pyNN:IF_cond_exp\n";
constexpr const char* kEdgeTypes =
    "edge_type_id population model_template receptor_type\n"
    "0 axonguide_to_axonguide pyNN:StaticSynapse excitatory\n";

std::string circuit_config(bool morphologies) {
  // Paths relative to the folder that holds this file, so that the run folder can move.
  const nlohmann::json components = morphologies ? nlohmann::json{{"morphologies_dir", "$BASE_DIR/morphologies"}}
                                                 : nlohmann::json::object();
  const nlohmann::json j = {
      {"manifest", {{"$BASE_DIR", "."}}},
      {"target_simulator", "PyNN"},
      {"components", components},
      {"networks",
       {{"nodes", {{{"nodes_file", "$BASE_DIR/nodes.h5"}, {"node_types_file", "$BASE_DIR/node_types.csv"}}}},
        {"edges", {{{"edges_file", "$BASE_DIR/edges.h5"}, {"edge_types_file", "$BASE_DIR/edge_types.csv"}}}}}}};
  return j.dump(2) + "\n";
}

}  // namespace

void write_sonata(const RunResult& r, const fs::path& dir, OutputInfo& info) {
  const fs::path net = dir / "network";
  create_output_dir(net);
  // nodes.h5 is hashed (from disk: HDF5 writes out of order) while edges.h5 is written.
  // An HDF5 failure names the file (HDF5 prints its own error stack on stderr).
  auto written = [&](const char* name, void (*write)(const RunResult&, const fs::path&)) {
    try {
      write(r, net);
    } catch (const Hdf5Error& e) {
      throw RunError(fmt::format("cannot write {}: {}", (net / name).string(), e.what()));
    }
  };
  std::string nodes_hash;
  tbb::task_group hashing;
  written("nodes.h5", write_nodes);
  hashing.run([&] { nodes_hash = sha256_file(net / "nodes.h5"); });
  try {
    written("edges.h5", write_edges);
  } catch (...) {
    try {
      hashing.wait();
    } catch (...) {  // edges.h5's failure is the one to report
    }
    throw;
  }
  hashing.wait();
  info.files.emplace_back("network/nodes.h5", nodes_hash);
  info.files.emplace_back("network/edges.h5", sha256_file(net / "edges.h5"));
  auto emit = [&](const char* name, const std::string& bytes) {
    info.files.emplace_back(std::string("network/") + name, write_file_atomically(net, name, bytes));
  };
  emit("node_types.csv", kNodeTypes);
  emit("edge_types.csv", kEdgeTypes);
  emit("circuit_config.json", circuit_config(r.scene.arbours.has_value()));
  if (r.scene.arbours) write_centred_swc(r, dir, "network/morphologies", info);
}

}  // namespace axg
