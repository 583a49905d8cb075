// ParaView output (output.vtk / --vtk): VTK XML PolyData files (.vtp, raw appended
// binary, little-endian, UInt64 block headers) and a .pvd collection that plays the
// growth as a time series. Frames: step 0, every output.frames_every steps, and the last.
//   vtk/somas.vtp           points: id, radius, status, component, level
//   vtk/sources.vtp         points: kind (+1 attractant, -1 repellent), emission, D, k, K_d
//   vtk/axons_NNNNNN.vtp    polylines of every axon up to step NNNNNN: cell id, status then
//   vtk/particles_NNNNNN.vtp particles at step NNNNNN: cue index (particle fields only)
//   growth.pvd              the collection, timestep = step
#include <algorithm>
#include <cstring>
#include <type_traits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "axonguide/io/canonical_nan.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/io/vtk.hpp"

namespace axg {

namespace fs = std::filesystem;

namespace {

class VtpWriter {
 public:
  explicit VtpWriter(std::size_t points) : points_(points) {}

  template <class T>
  void point_array(const std::string& name, const char* type, int components, const std::vector<T>& v) {
    arrays_.push_back({"point", name, type, components, bytes_of(v)});
  }
  template <class T>
  void cell_array(const std::string& name, const char* type, int components, const std::vector<T>& v) {
    arrays_.push_back({"cell", name, type, components, bytes_of(v)});
  }
  void coordinates(const std::vector<core::Vec3>& p) {
    coords_.resize(p.size() * 3);
    for (std::size_t i = 0; i < p.size(); ++i) coords_[3 * i] = p[i].x, coords_[3 * i + 1] = p[i].y, coords_[3 * i + 2] = p[i].z;
  }
  // Cells of one kind ("Verts" or "Lines"): connectivity and end offsets.
  void cells(const char* kind, std::vector<std::int64_t> connectivity, std::vector<std::int64_t> offsets) {
    cell_kind_ = kind;
    connectivity_ = std::move(connectivity);
    offsets_ = std::move(offsets);
  }

  std::string write(AtomicFile& f) const {
    std::string xml;
    std::vector<const std::string*> blocks;
    std::uint64_t offset = 0;
    auto array_xml = [&](const std::string& name, const char* type, int comps, const std::string& data) {
      const std::string s = fmt::format(R"(        <DataArray type="{}" Name="{}" NumberOfComponents="{}" format="appended" offset="{}"/>)"
                                        "\n",
                                        type, name, comps, offset);
      offset += 8 + data.size();
      blocks.push_back(&data);
      return s;
    };
    const std::size_t cells = offsets_.size();
    xml += "<?xml version=\"1.0\"?>\n";
    xml += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    xml += "  <PolyData>\n";
    xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" "
                       "NumberOfPolys=\"0\">\n",
                       points_, cell_kind_ == "Verts" ? cells : 0, cell_kind_ == "Lines" ? cells : 0);
    for (const char* where : {"point", "cell"}) {
      xml += std::string("      <") + (std::string(where) == "point" ? "PointData" : "CellData") + ">\n";
      for (const auto& a : arrays_)
        if (a.where == where) xml += array_xml(a.name, a.type, a.components, a.data);
      xml += std::string("      </") + (std::string(where) == "point" ? "PointData" : "CellData") + ">\n";
    }
    coords_bytes_ = bytes_of(coords_);
    xml += "      <Points>\n";
    xml += array_xml("Points", "Float64", 3, coords_bytes_);
    xml += "      </Points>\n";
    conn_bytes_ = bytes_of(connectivity_);
    off_bytes_ = bytes_of(offsets_);
    // One statement each: the offsets must follow the order of the appended blocks.
    xml += fmt::format("      <{}>\n", cell_kind_);
    xml += array_xml("connectivity", "Int64", 1, conn_bytes_);
    xml += array_xml("offsets", "Int64", 1, off_bytes_);
    xml += fmt::format("      </{}>\n", cell_kind_);
    xml += "    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
    f.write(xml);
    for (const std::string* b : blocks) {
      const std::uint64_t n = b->size();
      f.write(std::string_view(reinterpret_cast<const char*>(&n), 8));
      f.write(*b);
    }
    f.write("\n  </AppendedData>\n</VTKFile>\n");
    return {};
  }

 private:
  struct Array {
    std::string where, name;
    const char* type;
    int components;
    std::string data;
  };
  // Float64 arrays hold one NaN bit pattern (canonical()).
  template <class T>
  static std::string bytes_of(const std::vector<T>& v) {
    std::string s(v.size() * sizeof(T), '\0');
    if constexpr (std::is_same_v<T, double>) {
      for (std::size_t i = 0; i < v.size(); ++i) {
        const double x = canonical(v[i]);
        std::memcpy(s.data() + i * sizeof(double), &x, sizeof(double));
      }
    } else if (!v.empty()) {
      std::memcpy(s.data(), v.data(), s.size());
    }
    return s;
  }
  std::size_t points_;
  std::vector<Array> arrays_;
  std::vector<double> coords_;
  std::vector<std::int64_t> connectivity_, offsets_;
  std::string cell_kind_ = "Verts";
  mutable std::string coords_bytes_, conn_bytes_, off_bytes_;
};

void verts(VtpWriter& w, std::size_t n) {
  std::vector<std::int64_t> c(n), o(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = static_cast<std::int64_t>(i), o[i] = static_cast<std::int64_t>(i + 1);
  w.cells("Verts", std::move(c), std::move(o));
}

}  // namespace

std::vector<std::uint32_t> vtk_frame_steps(const RunResult& r) {
  std::vector<std::uint32_t> steps{0};
  for (std::uint32_t s = r.scene.output.frames_every; s < r.steps_run; s += r.scene.output.frames_every) steps.push_back(s);
  if (r.steps_run > 0) steps.push_back(r.steps_run);
  return steps;
}

void write_vtk(const RunResult& r, const fs::path& dir, OutputInfo& info) {
  const fs::path vdir = dir / "vtk";
  create_output_dir(vdir);
  auto emit = [&](const std::string& name, const VtpWriter& w) {
    AtomicFile f(vdir, name, AtomicFile::Sync::kDeferred);  // write_outputs syncs
    w.write(f);
    info.files.emplace_back("vtk/" + name, f.commit());
  };
  const std::size_t n = r.neurons.size();
  {
    VtpWriter w(n);
    w.coordinates(r.soma);
    std::vector<std::int64_t> id(n), component(n, -1);
    std::vector<double> radius(n, r.scene.neurons.soma_radius);
    std::vector<std::int32_t> status(n), level(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      id[i] = static_cast<std::int64_t>(i);
      status[i] = static_cast<std::int32_t>(r.neurons.status[i]);
      if (!r.graph.component.empty()) component[i] = r.graph.component[i];
      if (r.graph.bfs) level[i] = r.graph.bfs->level[i];
    }
    w.point_array("id", "Int64", 1, id);
    w.point_array("radius", "Float64", 1, radius);
    w.point_array("status", "Int32", 1, status);
    w.point_array("component", "Int64", 1, component);
    w.point_array("level", "Int32", 1, level);
    verts(w, n);
    emit("somas.vtp", w);
  }
  {
    VtpWriter w(r.cues.size());
    std::vector<core::Vec3> p;
    std::vector<std::int32_t> kind;
    std::vector<double> emission, diffusion, decay, kd;
    for (const auto& c : r.cues) {
      p.push_back(c.position);
      kind.push_back(c.sign > 0 ? 1 : -1);
      emission.push_back(c.emission);
      diffusion.push_back(c.diffusion);
      decay.push_back(c.decay);
      kd.push_back(c.kd);
    }
    w.coordinates(p);
    w.point_array("kind", "Int32", 1, kind);
    w.point_array("emission", "Float64", 1, emission);
    w.point_array("diffusion", "Float64", 1, diffusion);
    w.point_array("decay", "Float64", 1, decay);
    w.point_array("kd", "Float64", 1, kd);
    verts(w, p.size());
    emit("sources.vtp", w);
  }
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                    "  <Collection>\n";
  std::size_t frame_index = 0;
  // Arbours: every neuron's SWC samples, once.
  std::vector<std::vector<morphology::ArbourSample>> arbour(r.arbours.size());
  tbb::parallel_for(std::size_t{0}, r.arbours.size(), [&](std::size_t i) { arbour[i] = morphology::arbour_samples(r.arbours[i]); });
  for (std::uint32_t t : vtk_frame_steps(r)) {
    // Axons up to step t: path points 0..min(t, steps_i).
    std::vector<core::Vec3> pts;
    std::vector<std::int32_t> pstep, status;
    std::vector<std::int64_t> id, conn, offs;
    // Arbours up to step t: one polyline per cone with a point made by then, from its
    // parent's branch point (a stem from its first point), with the cone's neuron, index,
    // type and order.
    std::vector<std::int64_t> cone;
    std::vector<std::int32_t> type, order;
    for (std::size_t i = 0; i < arbour.size(); ++i) {
      const std::vector<morphology::ArbourSample>& s = arbour[i];
      for (std::size_t j = 0; j < s.size();) {
        std::size_t end = j;
        while (end < s.size() && s[end].cone == s[j].cone) ++end;  // one cone's samples: [j, end)
        if (s[j].step <= t) {
          if (s[j].parent > 1 && s[s[j].parent - 2].cone != s[j].cone) {  // from the branch point
            conn.push_back(static_cast<std::int64_t>(pts.size()));
            pts.push_back(s[s[j].parent - 2].pos);
            pstep.push_back(static_cast<std::int32_t>(s[s[j].parent - 2].step));
          }
          for (std::size_t k = j; k < end && s[k].step <= t; ++k) {
            conn.push_back(static_cast<std::int64_t>(pts.size()));
            pts.push_back(s[k].pos);
            pstep.push_back(static_cast<std::int32_t>(s[k].step));
          }
          offs.push_back(static_cast<std::int64_t>(pts.size()));
          id.push_back(static_cast<std::int64_t>(i));
          cone.push_back(static_cast<std::int64_t>(s[j].cone));
          type.push_back(s[j].type);
          order.push_back(s[j].order);
        }
        j = end;
      }
    }
    for (std::size_t i = 0; i < n && arbour.empty(); ++i) {
      const std::uint32_t last = std::min<std::uint32_t>(t, r.neurons.steps[i]);
      if (last >= r.paths.size()) continue;
      for (std::uint32_t s = 0; s <= last; ++s) {
        conn.push_back(static_cast<std::int64_t>(pts.size()));
        pts.push_back(r.paths[s][i]);
        pstep.push_back(static_cast<std::int32_t>(s));
      }
      offs.push_back(static_cast<std::int64_t>(pts.size()));
      id.push_back(static_cast<std::int64_t>(i));
      status.push_back(r.neurons.steps[i] <= t ? static_cast<std::int32_t>(r.neurons.status[i]) : 0);
    }
    VtpWriter w(pts.size());
    w.coordinates(pts);
    w.point_array("step", "Int32", 1, pstep);
    w.cell_array("id", "Int64", 1, id);
    if (arbour.empty()) {
      w.cell_array("status", "Int32", 1, status);
    } else {
      w.cell_array("cone", "Int64", 1, cone);
      w.cell_array("type", "Int32", 1, type);
      w.cell_array("order", "Int32", 1, order);
    }
    w.cells("Lines", std::move(conn), std::move(offs));
    const std::string axons = fmt::format("axons_{:06d}.vtp", t);
    emit(axons, w);
    pvd += fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"vtk/somas.vtp\"/>\n", t);
    pvd += fmt::format("    <DataSet timestep=\"{}\" part=\"1\" file=\"vtk/sources.vtp\"/>\n", t);
    pvd += fmt::format("    <DataSet timestep=\"{}\" part=\"2\" file=\"vtk/{}\"/>\n", t, axons);
    // The particle frame recorded at or just before t.
    while (frame_index + 1 < r.frames.size() && r.frames[frame_index + 1].step <= t) ++frame_index;
    if (!r.frames.empty() && r.frames[frame_index].step <= t) {
      const ParticleFrame& fr = r.frames[frame_index];
      VtpWriter pw(fr.pos.size());
      pw.coordinates(fr.pos);
      std::vector<std::int32_t> cue(fr.cue.begin(), fr.cue.end());
      pw.point_array("cue", "Int32", 1, cue);
      verts(pw, fr.pos.size());
      const std::string name = fmt::format("particles_{:06d}.vtp", t);
      emit(name, pw);
      pvd += fmt::format("    <DataSet timestep=\"{}\" part=\"3\" file=\"vtk/{}\"/>\n", t, name);
    }
  }
  pvd += "  </Collection>\n</VTKFile>\n";
  AtomicFile f(dir, "growth.pvd", AtomicFile::Sync::kDeferred);
  f.write(pvd);
  info.files.emplace_back("growth.pvd", f.commit());
}

}  // namespace axg
