// Particle caches: one OpenVDB file per output frame, holding one point data grid named
// "particles" with these attributes (documented for users in README.md):
//   P     vec3f  world position in metres, stored without a lossy codec: reading it back gives
//                the written float bit for bit
//   v     vec3f  velocity, m/s (no codec)
//   id    int64  stable particle id, unique within a run, kept from frame to frame
//   kind  int32  0 = fluid, k >= 1 = the k-th body of the scene (bodies[k-1])
//   rest_density_factor  float  rho0_i / rho0 of the particle's phase: L^dens (SPEC §3.3) for
//                body particles, 1 for fluid. Optional on reading (absent -> 1).
// and file metadata:
//   kurage:time   double  simulated time of the frame, seconds
//   kurage:frame  int32   output frame index
//   kurage:kinds  string  comma-separated names of the kinds, index = kind value
//   kurage:stage "sim", kurage:scene_hash, kurage:checksum: see pipeline/io/stamp.h
//
// The files are in OpenVDB's stream format (io::Stream; OpenVDB's io::File and vdb_print read
// them too), written atomically through pipeline/io, and checked before they are parsed.
#pragma once

#include "pipeline/io/stamp.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace kurage::pipeline {

struct ParticleFrame {
  double time = 0.0;
  int frame = 0;
  std::vector<std::string> kindNames{"fluid"};
  // Structure of arrays, all of the same length.
  std::vector<float> px, py, pz;
  std::vector<float> vx, vy, vz;
  std::vector<int64_t> id;
  std::vector<int32_t> kind;
  std::vector<float> restDensityFactor;  // empty when writing means all 1
  std::string sceneHash;                 // kurage:scene_hash: the simulation parameters' hash


  size_t size() const { return px.size(); }
};

// Writes the frame. Throws std::runtime_error naming the path on failure.
void writeParticleFrame(const std::filesystem::path& path, const ParticleFrame& frame);

// Reads a frame written by writeParticleFrame. Particles come back sorted by id. The checksum is
// verified before parsing and the stamp compared with `expected` (empty fields unchecked).
// Throws std::runtime_error (IoError) naming the path if it is missing, truncated, damaged,
// foreign (another scene's, another stage's, another frame's), or lacks an attribute.
ParticleFrame readParticleFrame(const std::filesystem::path& path, const FileStamp& expected = {"sim", "", -1});

}  // namespace kurage::pipeline
