#include "pipeline/exports.h"

#include "pipeline/io/files.h"
#include "pipeline/io/surface_file.h"
#include "pipeline/render_scene.h"
#include "pipeline/stages.h"
#include "render/surfacing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

// Little-endian bytes of trivially copyable values (x86-64 and AArch64 are little-endian).
template <class T>
void put(std::string& out, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out.push_back(table[(v >> s) & 63]);
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | (two ? uint32_t(uint8_t(bytes[i + 1])) << 8 : 0u);
    out.push_back(table[(v >> 18) & 63]);
    out.push_back(table[(v >> 12) & 63]);
    out.push_back(two ? table[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

// One VTK inline binary DataArray: a UInt32 byte count and the data, each base64-encoded on its
// own (as VTK's own writer does for uncompressed data).
template <class T>
std::string dataArray(const char* type, const char* name, int components, const std::vector<T>& values) {
  std::string raw;
  raw.reserve(values.size() * sizeof(T));
  for (const T& v : values) put(raw, v);
  std::string header;
  put(header, uint32_t(raw.size()));
  std::ostringstream s;
  s << "        <DataArray type=\"" << type << "\"";
  if (name) s << " Name=\"" << name << "\"";
  if (components > 1) s << " NumberOfComponents=\"" << components << "\"";
  s << " format=\"binary\">\n          " << base64(header) << base64(raw) << "\n        </DataArray>\n";
  return s.str();
}

std::string xmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out.push_back(c);
    }
  return out;
}

std::string vtkHeader() {
  return "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n"
         "  <PolyData>\n";
}

std::string timeFieldData(double time) {
  return "    <FieldData>\n" + dataArray("Float64", "TimeValue", 1, std::vector<double>{time}) + "    </FieldData>\n";
}

std::vector<float> interleave(const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z) {
  std::vector<float> out(3 * x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    out[3 * i] = x[i];
    out[3 * i + 1] = y[i];
    out[3 * i + 2] = z[i];
  }
  return out;
}

std::string fixed(float v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", double(v));
  return buffer;
}

}  // namespace

std::string meshToPly(const render::TriangleMesh& mesh) {
  const bool normals = mesh.normals.size() == mesh.positions.size() && !mesh.positions.empty();
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment kurage surface mesh, metres, z up\n"
    << "element vertex " << mesh.positions.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) h << "property float nx\nproperty float ny\nproperty float nz\n";
  h << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string out = h.str();
  out.reserve(out.size() + mesh.positions.size() * (normals ? 24 : 12) + mesh.triangles.size() * 13);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    for (int a = 0; a < 3; ++a) put(out, mesh.positions[i][a]);
    if (normals)
      for (int a = 0; a < 3; ++a) put(out, mesh.normals[i][a]);
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    put(out, uint8_t(3));
    for (int a = 0; a < 3; ++a) put(out, int32_t(t[a]));
  }
  return out;
}

std::string meshToObj(const render::TriangleMesh& mesh, const std::string& name) {
  const bool normals = mesh.normals.size() == mesh.positions.size() && !mesh.positions.empty();
  std::string out = "# kurage surface mesh, metres, z up\no " + name + "\n";
  for (const Eigen::Vector3f& p : mesh.positions) out += "v " + fixed(p.x()) + " " + fixed(p.y()) + " " + fixed(p.z()) + "\n";
  if (normals)
    for (const Eigen::Vector3f& n : mesh.normals) out += "vn " + fixed(n.x()) + " " + fixed(n.y()) + " " + fixed(n.z()) + "\n";
  for (const Eigen::Vector3i& t : mesh.triangles) {
    out += "f";
    for (int a = 0; a < 3; ++a) {
      const std::string v = std::to_string(t[a] + 1);
      out += " " + v + (normals ? "//" + v : "");
    }
    out += "\n";
  }
  return out;
}

std::string particlesToVtp(const ParticleFrame& frame) {
  const size_t n = frame.size();
  std::vector<int64_t> connectivity(n), offsets(n);
  for (size_t i = 0; i < n; ++i) {
    connectivity[i] = int64_t(i);
    offsets[i] = int64_t(i + 1);
  }
  std::vector<float> speed(n), factor(n, 1.0f);
  for (size_t i = 0; i < n; ++i)
    speed[i] = std::sqrt(frame.vx[i] * frame.vx[i] + frame.vy[i] * frame.vy[i] + frame.vz[i] * frame.vz[i]);
  if (frame.restDensityFactor.size() == n) factor = frame.restDensityFactor;
  std::string kinds;
  for (size_t k = 0; k < frame.kindNames.size(); ++k) kinds += (k ? "," : "") + frame.kindNames[k];

  std::ostringstream s;
  s << vtkHeader() << "    <FieldData>\n"
    << dataArray("Float64", "TimeValue", 1, std::vector<double>{frame.time})
    << dataArray("Int32", "frame", 1, std::vector<int32_t>{frame.frame})
    << "    </FieldData>\n"
    << "    <!-- kind names (index = kind value): " << xmlEscape(kinds) << " -->\n"
    << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"" << n
    << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
    << "      <PointData Scalars=\"kind\" Vectors=\"velocity\">\n"
    << dataArray("Float32", "velocity", 3, interleave(frame.vx, frame.vy, frame.vz))
    << dataArray("Float32", "speed", 1, speed) << dataArray("Int64", "id", 1, frame.id)
    << dataArray("Int32", "kind", 1, frame.kind) << dataArray("Float32", "rest_density_factor", 1, factor)
    << "      </PointData>\n"
    << "      <Points>\n" << dataArray("Float32", "Points", 3, interleave(frame.px, frame.py, frame.pz))
    << "      </Points>\n"
    << "      <Verts>\n" << dataArray("Int64", "connectivity", 1, connectivity)
    << dataArray("Int64", "offsets", 1, offsets) << "      </Verts>\n"
    << "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return s.str();
}

std::string particlesToPly(const ParticleFrame& frame) {
  const size_t n = frame.size();
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment kurage particles, metres, m/s, z up\ncomment kinds";
  for (const std::string& k : frame.kindNames) out += " " + k;
  out += "\nelement vertex " + std::to_string(n) +
         "\nproperty float x\nproperty float y\nproperty float z\nproperty float vx\nproperty float vy\n"
         "property float vz\nproperty int id\nproperty int kind\nproperty float rest_density_factor\nend_header\n";
  out.reserve(out.size() + n * 36);
  for (size_t i = 0; i < n; ++i) {
    if (frame.id[i] < 0 || frame.id[i] > std::numeric_limits<int32_t>::max())
      throw std::runtime_error("particle id " + std::to_string(frame.id[i]) + " does not fit PLY's int");
    for (float v : {frame.px[i], frame.py[i], frame.pz[i], frame.vx[i], frame.vy[i], frame.vz[i]}) put(out, v);
    put(out, int32_t(frame.id[i]));
    put(out, int32_t(frame.kind[i]));
    put(out, frame.restDensityFactor.size() == n ? frame.restDensityFactor[i] : 1.0f);
  }
  return out;
}

std::string polylinesToVtp(const std::vector<Polyline>& chains, double time) {
  std::vector<float> points;
  std::vector<int64_t> connectivity, offsets;
  std::vector<int32_t> kinds;
  for (const Polyline& c : chains) {
    for (const Eigen::Vector3f& p : c.points) {
      connectivity.push_back(int64_t(points.size() / 3));
      points.insert(points.end(), {p.x(), p.y(), p.z()});
    }
    offsets.push_back(int64_t(connectivity.size()));
    kinds.push_back(c.kind);
  }
  std::ostringstream s;
  s << vtkHeader() << timeFieldData(time) << "    <Piece NumberOfPoints=\"" << points.size() / 3
    << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << chains.size()
    << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
    << "      <CellData Scalars=\"kind\">\n" << dataArray("Int32", "kind", 1, kinds) << "      </CellData>\n"
    << "      <Points>\n" << dataArray("Float32", "Points", 3, points) << "      </Points>\n"
    << "      <Lines>\n" << dataArray("Int64", "connectivity", 1, connectivity)
    << dataArray("Int64", "offsets", 1, offsets) << "      </Lines>\n"
    << "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return s.str();
}

std::string polylinesToObj(const std::vector<Polyline>& chains) {
  std::string out = "# kurage chains (oral arms) as polylines, metres, z up\n";
  size_t base = 1;
  for (const Polyline& c : chains) {
    out += "o " + c.name + "\n";
    for (const Eigen::Vector3f& p : c.points) out += "v " + fixed(p.x()) + " " + fixed(p.y()) + " " + fixed(p.z()) + "\n";
    out += "l";
    for (size_t k = 0; k < c.points.size(); ++k) {
      out += ' ';
      out += std::to_string(base + k);
    }
    out += "\n";
    base += c.points.size();
  }
  return out;
}

std::string pvdCollection(const std::vector<std::pair<double, std::string>>& steps) {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    << "  <Collection>\n";
  char time[32];
  for (const auto& [t, file] : steps) {
    std::snprintf(time, sizeof time, "%.9g", t);
    s << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << xmlEscape(file) << "\"/>\n";
  }
  s << "  </Collection>\n</VTKFile>\n";
  return s.str();
}

std::vector<Polyline> chainPolylines(const Scene& scene, const ParticleFrame& frame) {
  std::vector<Polyline> chains;
  for (const ChainOrder& order : chainOrder(scene, frame)) {
    Polyline line;
    line.kind = order.kind;
    line.name = scene.sim.bodies[size_t(order.kind - 1)].name;
    for (size_t i : order.indices) line.points.emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
    chains.push_back(std::move(line));
  }
  return chains;
}

const char* exportFormatNames() {
  return "mesh_ply, mesh_obj, particles_vtp, particles_ply, chains_vtp, chains_obj, all";
}

ExportSelection parseExportFormats(const std::string& list) {
  ExportSelection s;
  std::stringstream in(list);
  std::string name;
  bool some = false;
  while (std::getline(in, name, ',')) {
    some = true;
    if (name == "all") s = {true, true, true, true, true, true};
    else if (name == "mesh_ply") s.meshPly = true;
    else if (name == "mesh_obj") s.meshObj = true;
    else if (name == "particles_vtp") s.particlesVtp = true;
    else if (name == "particles_ply") s.particlesPly = true;
    else if (name == "chains_vtp") s.chainsVtp = true;
    else if (name == "chains_obj") s.chainsObj = true;
    else throw std::invalid_argument("unknown export format '" + name + "'; valid: " + exportFormatNames());
  }
  if (!some) throw std::invalid_argument(std::string("no export format given; valid: ") + exportFormatNames());
  return s;
}

namespace {

void writeSeries(const Scene& scene, const fs::path& exportsDir, const std::string& folder, const char* extension) {
  std::vector<std::pair<double, std::string>> steps;
  for (int f = 0; f < scene.output.frameCount(); ++f) {
    const fs::path file = frameFile(exportsDir / folder, f, extension);
    if (fs::exists(file)) steps.emplace_back(scene.output.frameTime(f), folder + "/" + file.filename().string());
  }
  writeTextAtomic(exportsDir / (folder + ".pvd"), pvdCollection(steps));
}

}  // namespace

void exportFrames(const Scene& scene, const ExportSelection& selection, const fs::path& outDir, int first,
                  int last, const std::function<bool()>& stop) {
  const fs::path exportsDir = outDir / "exports";
  const bool particles = selection.particlesVtp || selection.particlesPly || selection.chainsVtp || selection.chainsObj;
  for (int f = first; f <= last; ++f) {
    if (stop && stop()) return;
    if (selection.needsSurfaces()) {
      const fs::path input = frameFile(outDir / "surfaces", f, "vdb");
      if (!fs::exists(input)) throw std::runtime_error(input.string() + ": missing; run `kurage surface` first");
      for (const auto& [grid, levelSet] : readSurfaceFile(input, {"surface", stageHash(scene, "surface"), f})) {
        const render::TriangleMesh mesh = render::meshLevelSet(levelSet);
        outputFolder(outDir, fs::path("exports") / grid);
        if (selection.meshPly) writeTextAtomic(frameFile(exportsDir / grid, f, "ply"), meshToPly(mesh));
        if (selection.meshObj) writeTextAtomic(frameFile(exportsDir / grid, f, "obj"), meshToObj(mesh, grid));
      }
    }
    if (!particles) continue;
    const fs::path input = frameFile(outDir / "particles", f, "vdb");
    if (!fs::exists(input)) throw std::runtime_error(input.string() + ": missing; run `kurage sim` first");
    const ParticleFrame frame = readParticleFrame(input, {"sim", stageHash(scene, "sim"), f});
    if (selection.particlesVtp || selection.particlesPly) outputFolder(outDir, "exports/particles");
    if (selection.particlesVtp) writeTextAtomic(frameFile(exportsDir / "particles", f, "vtp"), particlesToVtp(frame));
    if (selection.particlesPly) writeTextAtomic(frameFile(exportsDir / "particles", f, "ply"), particlesToPly(frame));
    if (selection.chainsVtp || selection.chainsObj) {
      const std::vector<Polyline> chains = chainPolylines(scene, frame);
      outputFolder(outDir, "exports/chains");
      if (selection.chainsVtp) writeTextAtomic(frameFile(exportsDir / "chains", f, "vtp"), polylinesToVtp(chains, frame.time));
      if (selection.chainsObj) writeTextAtomic(frameFile(exportsDir / "chains", f, "obj"), polylinesToObj(chains));
    }
  }
  if (selection.particlesVtp) writeSeries(scene, exportsDir, "particles", "vtp");
  if (selection.chainsVtp) writeSeries(scene, exportsDir, "chains", "vtp");
}

}  // namespace kurage::pipeline
