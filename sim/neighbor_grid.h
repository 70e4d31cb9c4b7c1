// Bucket (uniform grid) neighbour search (SPEC §1): particles are binned into cubic cells of
// edge >= h and re-sorted by cell with a counting sort, so that the candidates of a particle
// (its own cell and the 26 adjacent ones) are nine contiguous index ranges, one per (y, z)
// row of three cells along x. Cells are indexed x-fastest.
//
// The grid covers a fixed box (the container); positions outside it are clamped into the
// border cells, which keeps the search correct (only slower) for stray particles.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace kurage::sim {

class NeighborGrid {
public:
  // Covers [boxMin, boxMax] with cells of edge at least minCellSize (metres).
  void configure(const Eigen::Vector3f& boxMin, const Eigen::Vector3f& boxMax, float minCellSize);

  // Computes each particle's cell and the counting-sort order (order[k] = old index of the
  // particle that goes to position k). Afterwards cellStart() is valid for the sorted order.
  void sort(const float* x, const float* y, const float* z, size_t count, std::vector<uint32_t>& order);

  // After sort(): cellOfSorted()[k] is the cell of the k-th particle in sorted order.
  const std::vector<uint32_t>& cellOfSorted() const { return sortedCell_; }

  // The nine contiguous index ranges [begin, end) that hold every candidate neighbour of a
  // particle in `cell`. Returns how many ranges were written (rows outside the grid are skipped).
  int candidateRanges(uint32_t cell, std::array<std::array<uint32_t, 2>, 9>& ranges) const;

  Eigen::Vector3i dims() const { return dims_; }
  size_t memoryBytes() const {
    return (cellStart_.capacity() + cellOf_.capacity() + sortedCell_.capacity()) * sizeof(uint32_t);
  }
  float cellSize() const { return cellSize_; }
  uint32_t cellIndex(float x, float y, float z) const;

private:
  Eigen::Vector3f origin_{0, 0, 0};
  Eigen::Vector3i dims_{1, 1, 1};
  float cellSize_ = 1.0f;
  float inverseCellSize_ = 1.0f;
  std::vector<uint32_t> cellStart_;  // size cells + 1
  std::vector<uint32_t> cellOf_;     // by old index
  std::vector<uint32_t> sortedCell_; // by sorted index
};

// Per-particle neighbour lists (indices into the sorted particle arrays, the particle itself
// excluded), found once per step by the density pass and reused by the force passes, so that
// those loop over true neighbours only. Particles are split into fixed chunks, each with its own
// buffer: the lists are a deterministic function of the particle order whatever the threads,
// and the buffers are kept between steps (no allocation once sizes are stable).
class NeighborLists {
public:
  static constexpr size_t kChunk = 1024;

  void resize(size_t particles);
  size_t chunkCount() const { return chunks_.size(); }
  std::vector<uint32_t>& chunk(size_t c) { return chunks_[c]; }
  // The builder's scratch for chunk c, where its own does not suffice (kept between steps).
  std::vector<uint32_t>& scratch(size_t c) { return scratch_[c]; }

  // Called by the builder of chunk i / kChunk, in particle order within the chunk.
  void setRange(size_t i, uint32_t begin, uint32_t end) { begin_[i] = begin; end_[i] = end; }

  const uint32_t* begin(size_t i) const { return chunks_[i / kChunk].data() + begin_[i]; }
  const uint32_t* end(size_t i) const { return chunks_[i / kChunk].data() + end_[i]; }
  size_t count(size_t i) const { return end_[i] - begin_[i]; }
  // Offset of particle i's list in its chunk's buffer (for per-neighbour data kept alongside).
  uint32_t offset(size_t i) const { return begin_[i]; }
  // Size of chunk c's buffer.
  size_t chunkSize(size_t c) const { return chunks_[c].size(); }
  // Per neighbour entry, alongside chunk c's buffer: W'(r_ij) / r_ij of the cubic spline, filled
  // by the cubic density pass (which has r_ij at hand) for the gradients of the solvers that use
  // that kernel (DFSPH's, WCSPH's pressure force with fluid.kernel "cubic_spline") and for the
  // gradient correction's matrices (computeGradientCorrection); empty otherwise.
  std::vector<float>& slopes(size_t c) { return slopes_[c]; }
  const std::vector<float>& slopes(size_t c) const { return slopes_[c]; }
  size_t totalCount() const;
  size_t memoryBytes() const;

private:
  std::vector<std::vector<uint32_t>> chunks_;
  std::vector<std::vector<uint32_t>> scratch_;
  std::vector<std::vector<float>> slopes_;
  std::vector<uint32_t> begin_, end_;
};

}  // namespace kurage::sim
