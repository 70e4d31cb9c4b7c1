// Exports for other tools (Blender, ParaView, Houdini, MeshLab): per frame, from a run's caches
// (OUT/particles/NNNN.vdb) and surfaces (OUT/surfaces/NNNN.vdb), into OUT/exports/:
//   mesh_ply       <grid>/NNNN.ply   each level set (fluid, each body) meshed at 0: binary little-
//                                    endian PLY, float x y z nx ny nz per vertex, triangles
//   mesh_obj       <grid>/NNNN.obj   the same as Wavefront OBJ (v, vn, f v//vn), one object
//   particles_vtp  particles/NNNN.vtp  VTK XML PolyData: every particle a point and a vertex cell
//                                    (so ParaView draws them), point data velocity (3), speed, id
//                                    (Int64), kind (Int32), rest_density_factor; field data time and
//                                    the kind names; and particles.pvd, the time series
//   particles_ply  particles/NNNN.ply  binary PLY: x y z vx vy vz, id (int), kind (int),
//                                    rest_density_factor
//   chains_vtp     chains/NNNN.vtp   each chain body (oral arm) a polyline in chain order, cell data
//                                    kind; and chains.pvd
//   chains_obj     chains/NNNN.obj   the same as OBJ line elements (l), one object per chain
// Units are metres, seconds and kg/m³, z up, as in the scene. Every file is written atomically.
// The serializers are pure (bytes in a string), so tests read them back without files.
#pragma once

#include "pipeline/io/particle_cache.h"
#include "pipeline/scene.h"
#include "render/mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace kurage::pipeline {

// A chain body's particles in chain order (from where it hangs to its tip).
struct Polyline {
  std::string name;  // the body's name
  int kind = 0;      // its kind value in the caches
  std::vector<Eigen::Vector3f> points;
};

// Binary little-endian PLY with per-vertex normals (when the mesh has them).
std::string meshToPly(const render::TriangleMesh& mesh);
// Wavefront OBJ, one object named `name`; normals as vn when the mesh has them.
std::string meshToObj(const render::TriangleMesh& mesh, const std::string& name);
// VTK XML PolyData (base64 inline binary, UInt32 headers) with vertex cells and every attribute.
std::string particlesToVtp(const ParticleFrame& frame);
// Binary little-endian PLY of the particles and their attributes. Throws if an id exceeds int32.
std::string particlesToPly(const ParticleFrame& frame);
// VTK XML PolyData with one polyline cell per chain.
std::string polylinesToVtp(const std::vector<Polyline>& chains, double time);
// OBJ line elements, one object per chain.
std::string polylinesToObj(const std::vector<Polyline>& chains);
// A ParaView collection (.pvd): one DataSet per (time, file relative to the .pvd).
std::string pvdCollection(const std::vector<std::pair<double, std::string>>& steps);

// The chain bodies of a frame as polylines (chain order: by id, see chainTubes).
std::vector<Polyline> chainPolylines(const Scene& scene, const ParticleFrame& frame);

// "mesh_ply,particles_vtp" or "all" → a selection. Throws std::invalid_argument naming the
// unknown format and the valid ones.
ExportSelection parseExportFormats(const std::string& list);
// The valid names, comma separated.
const char* exportFormatNames();

// Writes the selected exports of frames [first, last] of the run in outDir, and the .pvd series
// (over every frame whose file exists, so a partial re-export keeps the whole series). Throws
// std::runtime_error naming a missing or unreadable input and what makes it. `stop` is asked
// before each frame: true returns at once (the frames written so far are whole; the caller says
// the run was interrupted).
void exportFrames(const Scene& scene, const ExportSelection& selection, const std::filesystem::path& outDir,
                  int first, int last, const std::function<bool()>& stop = {});

}  // namespace kurage::pipeline
