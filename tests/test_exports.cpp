// Exports for other tools (pipeline/exports.h): every format read back — by small readers of
// our own here (PLY, OBJ, VTK XML), and by VTK's own XML reader (python3-vtk9) — and the
// `kurage export` command on a real run.
#include "pipeline/exports.h"
#include "pipeline/io/files.h"
#include "pipeline/io/particle_cache.h"

#include "test_util.h"

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace kurage::pipeline {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A PLY file: header lines and the binary body after "end_header\n".
struct Ply {
  std::vector<std::string> header;
  std::string body;
};
Ply splitPly(const std::string& bytes) {
  Ply ply;
  const size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  std::istringstream in(bytes.substr(0, end));
  for (std::string line; std::getline(in, line);) ply.header.push_back(line);
  ply.body = bytes.substr(end + 11);
  return ply;
}
template <class T>
T at(const std::string& body, size_t offset) {
  T v;
  std::memcpy(&v, body.data() + offset, sizeof(T));
  return v;
}

render::TriangleMesh tetrahedron() {
  render::TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  for (const auto& p : m.positions) m.normals.push_back((p - Eigen::Vector3f(0.25f, 0.5f, 0.75f)).normalized());
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

ParticleFrame smallFrame() {
  ParticleFrame f;
  f.time = 1.25;
  f.frame = 30;
  f.kindNames = {"fluid", "bell"};
  for (int i = 0; i < 5; ++i) {
    f.px.push_back(float(i));
    f.py.push_back(-0.5f * float(i));
    f.pz.push_back(10.0f + float(i));
    f.vx.push_back(3.0f);
    f.vy.push_back(4.0f);
    f.vz.push_back(float(-i));
    f.id.push_back(100 + i);
    f.kind.push_back(i < 3 ? 0 : 1);
    f.restDensityFactor.push_back(i < 3 ? 1.0f : 0.8f);
  }
  return f;
}

TEST(Exports, MeshPlyHoldsEveryVertexNormalAndTriangle) {
  const render::TriangleMesh mesh = tetrahedron();
  const Ply ply = splitPly(meshToPly(mesh));
  EXPECT_EQ(ply.header[1], "format binary_little_endian 1.0");
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element vertex 4"), ply.header.end());
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "property float nz"), ply.header.end());
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element face 4"), ply.header.end());
  ASSERT_EQ(ply.body.size(), 4 * 24 + 4 * 13u);
  for (size_t v = 0; v < 4; ++v)
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(at<float>(ply.body, v * 24 + 4 * a), mesh.positions[v][a]);
      EXPECT_EQ(at<float>(ply.body, v * 24 + 12 + 4 * a), mesh.normals[v][a]);
    }
  for (size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(uint8_t(ply.body[96 + 13 * t]), 3);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(at<int32_t>(ply.body, 96 + 13 * t + 1 + 4 * a), mesh.triangles[t][a]);
  }
}

TEST(Exports, MeshObjHasOneBasedFacesWithNormals) {
  const std::string obj = meshToObj(tetrahedron(), "fluid");
  std::istringstream in(obj);
  std::map<std::string, int> count;
  std::vector<Eigen::Vector3f> v;
  std::string faces;
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    std::string tag;
    l >> tag;
    ++count[tag];
    if (tag == "v") {
      Eigen::Vector3f p;
      l >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    }
    if (tag == "f") faces += line.substr(1);
  }
  EXPECT_EQ(count["o"], 1);
  EXPECT_EQ(count["v"], 4);
  EXPECT_EQ(count["vn"], 4);
  EXPECT_EQ(count["f"], 4);
  EXPECT_EQ(v[3], Eigen::Vector3f(0, 0, 3));
  EXPECT_EQ(faces.substr(0, 12), " 1//1 3//3 2");
}

TEST(Exports, ParticlePlyHoldsEveryAttribute) {
  const ParticleFrame f = smallFrame();
  const Ply ply = splitPly(particlesToPly(f));
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element vertex 5"), ply.header.end());
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "property float rest_density_factor"), ply.header.end());
  ASSERT_EQ(ply.body.size(), 5 * 36u);
  for (size_t i = 0; i < 5; ++i) {
    const size_t o = i * 36;
    EXPECT_EQ(at<float>(ply.body, o + 8), f.pz[i]);
    EXPECT_EQ(at<float>(ply.body, o + 20), f.vz[i]);
    EXPECT_EQ(at<int32_t>(ply.body, o + 24), f.id[i]);
    EXPECT_EQ(at<int32_t>(ply.body, o + 28), f.kind[i]);
    EXPECT_EQ(at<float>(ply.body, o + 32), f.restDensityFactor[i]);
  }
}

// A reader-side check of VTK's XML format: the root and piece elements, and every inline binary
// DataArray's base64 decoding to a UInt32 byte count followed by exactly that many bytes, of the
// element count the piece declares.
std::string decode64(const std::string& text) {
  std::string out;
  uint32_t buffer = 0;
  int bits = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    else continue;
    buffer = buffer << 6 | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(char((buffer >> bits) & 0xff));
    }
  }
  return out;
}

std::map<std::string, std::string> vtkArrays(const std::string& xml) {
  EXPECT_NE(xml.find("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt32\">"),
            std::string::npos);
  std::map<std::string, std::string> arrays;
  const std::regex array(R"re(<DataArray type="(\w+)" Name="(\w+)"(?: NumberOfComponents="\d")? format="binary">\s*([A-Za-z0-9+/=]+)\s*</DataArray>)re");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), array); it != std::sregex_iterator(); ++it) {
    const std::string encoded = (*it)[3];
    // The header (4 bytes) is its own base64 group of 8 characters, then the data.
    const std::string header = decode64(encoded.substr(0, 8));
    const std::string data = decode64(encoded.substr(8));
    EXPECT_EQ(at<uint32_t>(header, 0), data.size()) << (*it)[2];
    arrays[(*it)[2]] = data;
  }
  return arrays;
}

TEST(Exports, ParticleVtpIsWellFormedVtkXmlWithEveryAttribute) {
  const ParticleFrame f = smallFrame();
  const std::string xml = particlesToVtp(f);
  EXPECT_NE(xml.find("NumberOfPoints=\"5\" NumberOfVerts=\"5\""), std::string::npos);
  const auto arrays = vtkArrays(xml);
  for (const char* name : {"Points", "velocity", "speed", "id", "kind", "rest_density_factor", "connectivity", "offsets",
                           "TimeValue"})
    EXPECT_TRUE(arrays.count(name)) << name;
  ASSERT_EQ(arrays.at("Points").size(), 5 * 12u);
  EXPECT_EQ(at<float>(arrays.at("Points"), 4 * 12 + 8), 14.0f);
  EXPECT_EQ(at<float>(arrays.at("speed"), 0), 5.0f);
  EXPECT_EQ(at<int64_t>(arrays.at("id"), 2 * 8), 102);
  EXPECT_EQ(at<int32_t>(arrays.at("kind"), 4 * 4), 1);
  EXPECT_EQ(at<int64_t>(arrays.at("offsets"), 4 * 8), 5);
  EXPECT_EQ(at<double>(arrays.at("TimeValue"), 0), 1.25);
}

TEST(Exports, PvdListsEveryStep) {
  const std::string pvd = pvdCollection({{0.0, "particles/0000.vtp"}, {0.5, "particles/0001.vtp"}});
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(pvd.find("timestep=\"0.5\" part=\"0\" file=\"particles/0001.vtp\""), std::string::npos);
}

TEST(Exports, UnknownFormatsAreRefusedNamingTheValidOnes) {
  EXPECT_TRUE(parseExportFormats("all").chainsObj);
  const ExportSelection s = parseExportFormats("mesh_ply,chains_vtp");
  EXPECT_TRUE(s.meshPly && s.chainsVtp && !s.meshObj && !s.particlesVtp);
  try {
    parseExportFormats("mesh_ply,stl");
    FAIL() << "stl accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'stl'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("particles_vtp"), std::string::npos);
  }
}

TEST(Exports, SceneOutputExportsAreWrittenByRun) {
  // output.exports in the scene: `kurage run` writes them after the surfaces, and records the stage.
  TempDir dir;
  nlohmann::json scene = nlohmann::json::parse(slurp(test::sourceDir() / "tests/scenes/tiny_dam_break.json"));
  scene.erase("$schema");
  scene["output"]["exports"] = {{"mesh_ply", true}, {"particles_vtp", true}};
  writeTextAtomic(dir.path() / "scene.json", scene.dump());
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(test::runKurage("run " + (dir.path() / "scene.json").string() + " -o " + out.string() +
                                " --frames 0-1 --no-video",
                            dir.path() / "log.txt"), 0) << slurp(dir.path() / "log.txt");
  for (int f = 0; f <= 1; ++f) {
    EXPECT_TRUE(fs::exists(frameFile(out / "exports/fluid", f, "ply"))) << f;
    EXPECT_TRUE(fs::exists(frameFile(out / "exports/particles", f, "vtp"))) << f;
    EXPECT_FALSE(fs::exists(frameFile(out / "exports/fluid", f, "obj"))) << "not asked for";
  }
  EXPECT_NE(slurp(out / "exports/particles.pvd").find("particles/0001.vtp"), std::string::npos);
  const nlohmann::json run = nlohmann::json::parse(slurp(out / "run.json"));
  EXPECT_EQ(run["stages"]["export"]["frames"], 2);
}

// A run of the tiny jellyfish (two frames), then `kurage export OUT --format all`: every file read
// back and checked against the caches; VTK's own reader opens the .vtp and .pvd files.
class ExportRun : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const fs::path scene = test::sourceDir() / "tests/scenes/tiny_jellyfish.json";
    const std::string out = (dir_->path() / "out").string();
    ASSERT_EQ(test::runKurage("sim " + scene.string() + " -o " + out + " --frames 0-1", dir_->path() / "l1.txt"), 0);
    ASSERT_EQ(test::runKurage("surface " + scene.string() + " -o " + out + " --frames 0-1", dir_->path() / "l2.txt"), 0);
    exportStatus_ = test::runKurage("export " + out + " --format all --frames 0-1", dir_->path() / "l3.txt");
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path out() { return dir_->path() / "out"; }
  static inline TempDir* dir_ = nullptr;
  static inline int exportStatus_ = -1;
};

TEST_F(ExportRun, WritesEveryFormatMatchingTheCaches) {
  ASSERT_EQ(exportStatus_, 0) << slurp(dir_->path() / "l3.txt");
  const ParticleFrame frame = readParticleFrame(out() / "particles/0001.vdb");
  const Ply ply = splitPly(slurp(out() / "exports/particles/0001.ply"));
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element vertex " + std::to_string(frame.size())),
            ply.header.end());
  const auto arrays = vtkArrays(slurp(out() / "exports/particles/0001.vtp"));
  ASSERT_EQ(arrays.at("Points").size(), 12 * frame.size());
  for (size_t i = 0; i < frame.size(); ++i) EXPECT_EQ(at<float>(arrays.at("Points"), 12 * i + 4), frame.py[i]);
  // Surfaces: one mesh per grid (fluid, bell) in both formats, inside the container.
  // The container of tests/scenes/tiny_jellyfish.json is 0..8 x 0..6 x 0..9 m; surfaces are clipped
  // to it (a quarter voxel of margin), so every vertex lies within half a voxel (0.125 m) of it.
  for (const char* grid : {"fluid", "bell"}) {
    const Ply mesh = splitPly(slurp(out() / "exports" / grid / "0001.ply"));
    EXPECT_GT(mesh.body.size(), 1000u) << grid;
    EXPECT_TRUE(fs::exists(out() / "exports" / grid / "0001.obj")) << grid;
    size_t vertices = 0;
    for (const std::string& line : mesh.header)
      if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    ASSERT_GT(vertices, 0u) << grid;
    ASSERT_GE(mesh.body.size(), vertices * 24) << grid;  // x y z nx ny nz, float
    const Eigen::Vector3f lo(0, 0, 0), hi(8, 6, 9);
    for (size_t v = 0; v < vertices; ++v) {
      float xyz[6];
      std::memcpy(xyz, mesh.body.data() + 24 * v, sizeof xyz);
      const Eigen::Vector3f p(xyz[0], xyz[1], xyz[2]), n(xyz[3], xyz[4], xyz[5]);
      ASSERT_TRUE((p.array() >= lo.array() - 0.125f).all() && (p.array() <= hi.array() + 0.125f).all())
          << grid << " vertex " << v << " at " << p.transpose();
      ASSERT_NEAR(n.norm(), 1.0f, 1e-3f) << grid << " vertex " << v;
    }
  }
  // Chains: the tiny jellyfish's two arms, each a polyline through all its particles in id order.
  std::map<int, int> armParticles;
  for (size_t i = 0; i < frame.size(); ++i)
    if (frame.kind[i] >= 2) ++armParticles[frame.kind[i]];
  ASSERT_EQ(armParticles.size(), 2u);
  const std::string xml = slurp(out() / "exports/chains/0001.vtp");
  EXPECT_NE(xml.find("NumberOfLines=\"2\""), std::string::npos);
  const auto chain = vtkArrays(xml);
  EXPECT_EQ(at<int64_t>(chain.at("offsets"), 8), armParticles[2] + armParticles[3]);
  const std::string obj = slurp(out() / "exports/chains/0001.obj");
  EXPECT_NE(obj.find("o arm1\n"), std::string::npos);
  EXPECT_NE(obj.find("o arm2\n"), std::string::npos);
  const std::string pvd = slurp(out() / "exports/particles.pvd");
  EXPECT_NE(pvd.find("file=\"particles/0000.vtp\""), std::string::npos);
  EXPECT_NE(pvd.find("file=\"particles/0001.vtp\""), std::string::npos);
}

TEST_F(ExportRun, VtkOwnReaderOpensTheParticles) {
  ASSERT_EQ(exportStatus_, 0);
  const ParticleFrame frame = readParticleFrame(out() / "particles/0001.vdb");
  const fs::path script = dir_->path() / "read.py";
  std::ofstream(script) << "import sys, vtk\n"
                           "r = vtk.vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
                           "p = r.GetOutput(); d = p.GetPointData()\n"
                           "names = sorted(d.GetArrayName(i) for i in range(d.GetNumberOfArrays()))\n"
                           "print(p.GetNumberOfPoints(), p.GetNumberOfVerts(), ','.join(names))\n";
  const fs::path log = dir_->path() / "vtk.txt";
  const std::string command = "/usr/bin/python3 " + script.string() + " " +
                              (out() / "exports/particles/0001.vtp").string() + " > " + log.string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << slurp(log);
  EXPECT_EQ(slurp(log), std::to_string(frame.size()) + " " + std::to_string(frame.size()) +
                            " id,kind,rest_density_factor,speed,velocity\n");
  // The chains: VTK reads two polylines through the arms' particles.
  std::ofstream(dir_->path() / "lines.py") << "import sys, vtk\n"
                                             "r = vtk.vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
                                             "p = r.GetOutput()\n"
                                             "print(p.GetNumberOfLines(), p.GetNumberOfPoints())\n";
  size_t arms = 0;
  for (size_t i = 0; i < frame.size(); ++i) arms += frame.kind[i] >= 2;
  const std::string lines = "/usr/bin/python3 " + (dir_->path() / "lines.py").string() + " " +
                            (out() / "exports/chains/0001.vtp").string() + " > " + log.string() + " 2>&1";
  ASSERT_EQ(std::system(lines.c_str()), 0) << slurp(log);
  EXPECT_EQ(slurp(log), "2 " + std::to_string(arms) + "\n");
}

TEST_F(ExportRun, BadFormatOrMissingRunIsAUsageError) {
  EXPECT_EQ(test::runKurage("export " + out().string() + " --format stl", dir_->path() / "b1.txt"), 2);
  EXPECT_NE(slurp(dir_->path() / "b1.txt").find("mesh_ply"), std::string::npos);
  EXPECT_EQ(test::runKurage("export " + (dir_->path() / "none").string() + " --format all", dir_->path() / "b2.txt"), 2);
  EXPECT_NE(slurp(dir_->path() / "b2.txt").find("run.json"), std::string::npos);
}

}  // namespace
}  // namespace kurage::pipeline
