// The pressure solvers' SIMD sweeps (sim/solvers/sweeps.h): each path this CPU runs against the
// scalar one, sum by sum on random neighbourhoods and over whole runs (a DFSPH dam break, a body
// coupled as the fluid's boundary, IISPH), and 1 and 2 threads bit for bit on every path. The
// paths are forced with KURAGE_SIMD, as a user would.
#include "sim/solvers/sweeps.h"
#include "sim/simulation.h"
#include "sim_util.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace kurage::sim;
using solvers::Float4;
using solvers::SweepIsa;

namespace {

// KURAGE_SIMD set for the scope (unset after).
class ForcePath {
public:
  explicit ForcePath(const char* name) { setenv("KURAGE_SIMD", name, 1); }
  ~ForcePath() { unsetenv("KURAGE_SIMD"); }
};

std::vector<SweepIsa> simdPaths() {
  std::vector<SweepIsa> out;
  for (SweepIsa isa : {SweepIsa::Avx2, SweepIsa::Avx512})
    if (solvers::sweepSupported(isa)) out.push_back(isa);
  return out;
}

// The largest |a - b| over two runs' positions by id, in metres (infinite for other particles).
double largestDifference(const std::vector<std::array<float, 4>>& a, const std::vector<std::array<float, 4>>& b) {
  if (a.size() != b.size()) return INFINITY;
  double most = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    if (a[k][0] != b[k][0]) return INFINITY;
    for (int c = 1; c < 4; ++c) most = std::max(most, std::fabs(double(a[k][c]) - double(b[k][c])));
  }
  return most;
}

// A dam break: a 6 x 6 x 8 m column at 0.5 m in a 12 x 6 x 10 m tank of boundary particles.
SimParams damBreak(const std::string& solver) {
  SimParams p;
  p.fluid.spacing = 0.5f;
  p.fluid.supportRadius = 2.0f;
  p.fluid.solver = solver;
  p.fluid.kinematicViscosity = 0.01f;
  p.fluid.initialState = InitialState::Lattice;
  p.container.max = Eigen::Vector3f(12, 6, 10);
  p.container.walls = WallSlip::FreeSlip;
  p.container.wallDensity = WallDensity::BoundaryParticles;
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(4, 6, 8)});
  return p;
}

// A block of fluid thrown at a box body coupled as its boundary (DFSPH, density_sum "volume").
SimParams thrownAtABody() {
  SimParams p;
  p.gravity = Eigen::Vector3f::Zero();
  p.container.max = Eigen::Vector3f(12, 12, 12);
  p.fluid.spacing = 0.5f;
  p.fluid.solver = "dfsph";
  p.fluid.densitySum = DensitySum::Volume;
  p.fluidBlocks.push_back({Eigen::Vector3f(2, 4, 4), Eigen::Vector3f(5, 8, 8)});
  BodyParams box = kurage::test::boxBody(Eigen::Vector3f(5.75f, 4.5f, 4.5f), Eigen::Vector3f(7.25f, 7.5f, 7.5f));
  box.coupling = BodyCoupling::Boundary;
  box.stiffness = 2000.0f;
  p.bodies.push_back(box);
  return p;
}

// Positions by id after `seconds` on path `path` with `threads` threads (fluid thrown at 3 m/s
// along x where `thrown`).
std::vector<std::array<float, 4>> run(const SimParams& params, const char* path, int threads, double seconds,
                                      bool thrown = false) {
  ForcePath force(path);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  Simulation sim(params);
  if (thrown)
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (sim.particles().kind[i] == 0) sim.particles().vx[i] = 3.0f;
  sim.advanceTo(seconds);
  return kurage::test::positionsById(sim.particles());
}

// Neighbour lists for n particles over two chunks: particle i has (7 i) mod 41 random neighbours
// (0 to 40: a group's lanes of different lengths), each with a random slope.
NeighborLists randomLists(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  NeighborLists lists;
  lists.resize(n);
  for (size_t i = 0; i < n; ++i) {
    std::vector<uint32_t>& buffer = lists.chunk(i / NeighborLists::kChunk);
    std::vector<float>& slopes = lists.slopes(i / NeighborLists::kChunk);
    const uint32_t begin = uint32_t(buffer.size());
    for (size_t c = (i * 7) % 41; c > 0; --c) {
      buffer.push_back(uint32_t(rng() % n));
      slopes.push_back(-1.0f + 0.5f * u(rng));
    }
    lists.setRange(i, begin, uint32_t(buffer.size()));
  }
  return lists;
}

bool sameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

}  // namespace

TEST(Sweeps, KurageSimdChoosesThePathAndRefusesOthers) {
  unsetenv("KURAGE_SIMD");
  EXPECT_EQ(solvers::sweepTable().isa, solvers::sweepSupported(SweepIsa::Lanes) ? SweepIsa::Lanes : SweepIsa::Scalar)
      << "unset: the lanes path where the CPU runs AVX2, else the scalar one";
  {
    ForcePath force("scalar");
    EXPECT_EQ(solvers::sweepTable().isa, SweepIsa::Scalar);
  }
  for (SweepIsa isa : simdPaths()) {
    ForcePath force(solvers::sweepTable(isa).name);
    EXPECT_EQ(solvers::sweepTable().isa, isa);
  }
  ForcePath force("avx1024");
  EXPECT_THROW(solvers::sweepTable(), std::invalid_argument);
}

// Each sum of each SIMD path within 1e-5 of the sum of its terms' magnitudes of the scalar path's,
// on lists of 0 to 40 neighbours (every tail length of both widths).
TEST(Sweeps, SimdSumsMatchTheScalarOnesOnRandomNeighbourhoods) {
  if (simdPaths().empty()) GTEST_SKIP() << "this CPU runs no SIMD path";
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const size_t n = 64;
  std::vector<Float4> x(n), v(n);
  std::vector<float> k(n), response(n);
  for (size_t j = 0; j < n; ++j) {
    x[j] = Float4{u(rng), u(rng), u(rng), 1.0f + 0.5f * u(rng)};
    v[j] = Float4{u(rng), u(rng), u(rng), 0.0f};
    k[j] = 2.0f + u(rng);
    response[j] = 1.0f + 0.5f * u(rng);
  }
  const solvers::SweepTable& scalar = solvers::sweepTable(SweepIsa::Scalar);
  for (SweepIsa isa : simdPaths()) {
    const solvers::SweepTable& simd = solvers::sweepTable(isa);
    for (uint32_t count = 0; count <= 40; ++count) {
      std::vector<uint32_t> list(count);
      std::vector<float> slope(count);
      for (uint32_t c = 0; c < count; ++c) {
        list[c] = uint32_t(rng() % n);
        slope[c] = -1.0f + 0.5f * u(rng);
      }
      const uint32_t* b = list.data();
      const uint32_t* e = b + count;
      const Float4 xi = x[0], vi = v[1];
      // The terms' magnitudes: |w_j s_ij| |x_i - x_j| (|v_i - v_j| + |k_i + k_j| + ...) bound every sum's
      double scale = 1e-30;
      for (uint32_t c = 0; c < count; ++c) scale += std::fabs(slope[c]) * 16.0;
      const std::string at = std::string(simd.name) + ", " + std::to_string(count) + " neighbours";
      EXPECT_NEAR(simd.rate(b, e, slope.data(), x.data(), v.data(), xi, vi),
                  scalar.rate(b, e, slope.data(), x.data(), v.data(), xi, vi), 1e-5 * scale) << at;
      const Float4 ps = scalar.push(b, e, slope.data(), x.data(), k.data(), xi, k[0]);
      const Float4 pv = simd.push(b, e, slope.data(), x.data(), k.data(), xi, k[0]);
      Float4 fs = {0.5f, -0.5f, 0.25f, 0.0f}, fv = fs;
      float ss = 1.0f, sv = 1.0f;
      scalar.factor(b, e, slope.data(), x.data(), response.data(), xi, fs, ss);
      simd.factor(b, e, slope.data(), x.data(), response.data(), xi, fv, sv);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(pv[a], ps[a], 1e-5 * scale) << at << ", push axis " << a;
        EXPECT_NEAR(fv[a], fs[a], 1e-5 * scale) << at << ", factor axis " << a;
      }
      EXPECT_NEAR(sv, ss, 1e-5 * scale * 16.0) << at << ", factor's squares";
    }
  }
}

// The lanes path's sums (rate, push, factor), lane by lane, are the scalar sums bit for bit, over
// two chunks of particles whose lists have 0 to 40 neighbours (a group's lanes of different
// lengths, the last group short of 8 particles), and every particle is in one group of its chunk.
TEST(Sweeps, LanesSumsAreTheScalarSumsBitForBit) {
  if (!solvers::sweepSupported(SweepIsa::Lanes)) GTEST_SKIP() << "this CPU runs no AVX2";
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const size_t n = NeighborLists::kChunk + 45;
  std::vector<Float4> x(n), v(n);
  std::vector<float> k(n), response(n);
  for (size_t j = 0; j < n; ++j) {
    x[j] = Float4{u(rng), u(rng), u(rng), 1.0f + 0.5f * u(rng)};
    v[j] = Float4{u(rng), u(rng), u(rng), 0.0f};
    k[j] = u(rng);
    response[j] = 1.0f + 0.5f * u(rng);
  }
  const NeighborLists lists = randomLists(n, rng);
  solvers::LaneLists lanes;
  lanes.build(lists, n);
  ASSERT_EQ(lanes.groups.size(), (n + 7) / 8);
  const solvers::SweepTable& path = solvers::sweepTable(SweepIsa::Lanes);
  std::vector<int> seen(n, 0);
  for (size_t ch = 0; ch < lists.chunkCount(); ++ch) {
    const solvers::LaneRow* rows = lanes.rows[ch].data();
    const float* slopes = lists.slopes(ch).data();
    for (size_t gi = lanes.groupsBegin(ch); gi < lanes.groupsEnd(ch); ++gi) {
      const solvers::LaneGroup& g = lanes.groups[gi];
      float rate[8];
      Float4 push[8], F[8], F0[8];
      float S[8] = {};
      path.rateLanes(rows, g, x.data(), v.data(), rate);
      path.pushLanes(rows, g, x.data(), k.data(), push);
      for (int l = 0; l < 8; ++l) F[l] = F0[l] = Float4{0.5f * u(rng), u(rng), -0.25f, 0.0f};
      path.factorLanes(rows, g, x.data(), response.data(), F, S);
      for (uint32_t l = 0; l < g.used; ++l) {
        const size_t i = g.self[l];
        ASSERT_EQ(i / NeighborLists::kChunk, ch);
        ++seen[i];
        const float* s = slopes + lists.offset(i);
        const Float4 r = solvers::rateSum(lists.begin(i), lists.end(i), s, x.data(), v.data(), x[i], v[i]);
        const Float4 a = solvers::pushSum(lists.begin(i), lists.end(i), s, x.data(), k.data(), x[i], k[i]);
        Float4 f = F0[l];
        float sq = 0.0f;
        solvers::sweepTable(SweepIsa::Scalar).factor(lists.begin(i), lists.end(i), s, x.data(), response.data(), x[i], f, sq);
        const std::string at = "particle " + std::to_string(i) + ", " + std::to_string(lists.count(i)) + " neighbours";
        EXPECT_EQ(std::bit_cast<uint32_t>(rate[l]), std::bit_cast<uint32_t>(r[0] + r[1] + r[2])) << at;
        EXPECT_EQ(std::bit_cast<uint32_t>(S[l]), std::bit_cast<uint32_t>(sq)) << at << ", factor's squares";
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(std::bit_cast<uint32_t>(push[l][c]), std::bit_cast<uint32_t>(a[c])) << at << ", push axis " << c;
          EXPECT_EQ(std::bit_cast<uint32_t>(F[l][c]), std::bit_cast<uint32_t>(f[c])) << at << ", factor axis " << c;
        }
      }
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; })) << "every particle once";
}

// The lanes path's sums with the corrected gradient (rate, factor, push: solver_common.h's
// correctedRateSum, correctedFactorSum, correctedPushSum), lane by lane, are the scalar sums bit
// for bit, on the random neighbourhoods above with a random symmetric L_i per particle.
TEST(Sweeps, LanesCorrectedSumsAreTheScalarSumsBitForBit) {
  if (!solvers::sweepSupported(SweepIsa::Lanes)) GTEST_SKIP() << "this CPU runs no AVX2";
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const size_t n = NeighborLists::kChunk + 45;
  std::vector<Float4> x(n), v(n), correction(3 * n), terms(2 * n);
  std::vector<float> response(n), z(n);
  for (size_t j = 0; j < n; ++j) {
    x[j] = Float4{u(rng), u(rng), u(rng), 1.0f + 0.5f * u(rng)};
    v[j] = Float4{u(rng), u(rng), u(rng), 0.0f};
    response[j] = 1.0f + 0.5f * u(rng);
    const float l00 = 1.0f + 0.3f * u(rng), l11 = 1.0f + 0.3f * u(rng), l22 = 1.0f + 0.3f * u(rng);
    const float l01 = 0.2f * u(rng), l02 = 0.2f * u(rng), l12 = 0.2f * u(rng);
    correction[3 * j] = Float4{l00, l01, l02, 0.0f};
    correction[3 * j + 1] = Float4{l01, l11, l12, 0.0f};
    correction[3 * j + 2] = Float4{l02, l12, l22, 0.0f};
    terms[2 * j] = Float4{u(rng), u(rng), u(rng), u(rng)};
    terms[2 * j + 1] = Float4{u(rng), u(rng), 10.0f * u(rng), 10.0f * u(rng)};
    z[j] = 10.0f * u(rng);
  }
  const NeighborLists lists = randomLists(n, rng);
  solvers::LaneLists lanes;
  lanes.build(lists, n);
  const solvers::SweepTable& path = solvers::sweepTable(SweepIsa::Lanes);
  ASSERT_NE(path.rateCorrectedLanes, nullptr);
  size_t checked = 0;
  for (size_t ch = 0; ch < lists.chunkCount(); ++ch) {
    const solvers::LaneRow* rows = lanes.rows[ch].data();
    const float* slopes = lists.slopes(ch).data();
    for (size_t gi = lanes.groupsBegin(ch); gi < lanes.groupsEnd(ch); ++gi) {
      const solvers::LaneGroup& g = lanes.groups[gi];
      Float4 t[24], plain[8], m[16];
      float S[8], y2[8];
      path.rateCorrectedLanes(rows, g, x.data(), v.data(), t);
      path.factorCorrectedLanes(rows, g, x.data(), response.data(), correction.data(), plain, S);
      path.pushCorrectedLanes(rows, g, terms.data(), z.data(), m, y2);
      for (uint32_t l = 0; l < g.used; ++l) {
        const size_t i = g.self[l];
        const float* s = slopes + lists.offset(i);
        Float4 tr[3], pr, m0, m1;
        float sr, yr;
        solvers::correctedRateSum(lists.begin(i), lists.end(i), s, x.data(), v.data(), x[i], v[i], tr);
        solvers::correctedFactorSum(lists.begin(i), lists.end(i), s, x.data(), response.data(), x[i],
                                    correction.data() + 3 * i, pr, sr);
        solvers::correctedPushSum(lists.begin(i), lists.end(i), s, terms.data(), z.data(), m0, m1, yr);
        const std::string at = "particle " + std::to_string(i) + ", " + std::to_string(lists.count(i)) + " neighbours";
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) EXPECT_TRUE(sameBits(t[3 * l + a][b], tr[a][b])) << at << ", rate T" << a << b;
        for (int b = 0; b < 3; ++b) EXPECT_TRUE(sameBits(plain[l][b], pr[b])) << at << ", factor axis " << b;
        EXPECT_TRUE(sameBits(S[l], sr)) << at << ", factor's squares";
        for (int b = 0; b < 4; ++b) {
          EXPECT_TRUE(sameBits(m[2 * l][b], m0[b])) << at << ", push M " << b;
          EXPECT_TRUE(sameBits(m[2 * l + 1][b], m1[b])) << at << ", push M/Y " << b;
        }
        EXPECT_TRUE(sameBits(y2[l], yr)) << at << ", push Y2";
        if (lists.count(i) > 0) {
          EXPECT_NE(sr, 0.0f) << at;
        }
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, n) << "every particle once";
}

// The force pass's viscosity on the lanes path (fluid.h's ViscosityLanes) is the scalar force
// pass's, bit for bit, particle by particle: two chunks of random neighbourhoods (0 to 40
// neighbours, some within the support, some beyond it, a particle its own neighbour: the
// coincident pair's r = 0), a group's lanes of different lengths, the last group short of 8.
TEST(Sweeps, LanesViscosityIsTheScalarForcePassBitForBit) {
  if (!solvers::sweepSupported(SweepIsa::Lanes)) GTEST_SKIP() << "this CPU runs no AVX2";
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const size_t n = NeighborLists::kChunk + 45;
  ParticleSet particles;
  for (size_t j = 0; j < n; ++j)
    particles.add(1.5f * u(rng), 1.5f * u(rng), 1.5f * u(rng), u(rng), u(rng), u(rng), 1000.0f,
                  1.0f + 0.5f * u(rng), int64_t(j), 0);
  for (size_t j = 0; j < n; ++j) particles.density[j] = 1000.0f + 100.0f * u(rng);
  NeighborLists lists;
  lists.resize(n);
  for (size_t i = 0; i < n; ++i) {
    std::vector<uint32_t>& buffer = lists.chunk(i / NeighborLists::kChunk);
    const uint32_t begin = uint32_t(buffer.size());
    for (size_t c = (i * 7) % 41; c > 0; --c) buffer.push_back(c == 3 ? uint32_t(i) : uint32_t(rng() % n));
    lists.setRange(i, begin, uint32_t(buffer.size()));
    lists.slopes(i / NeighborLists::kChunk).resize(buffer.size(), 0.0f);
  }
  solvers::LaneLists lanes;
  lanes.build(lists, n);
  const float h = 2.0f;
  const SpikyKernel spiky(h);
  const ViscosityKernel viscosity(h);
  const Eigen::Vector3f g(0.0f, 0.0f, -9.81f);
  const auto accelerations = [&](ViscosityLanes* path) {
    computeFluidAcceleration(lists, particles, GradientKernel{&spiky, nullptr}, viscosity, 10.0f, g,
                             PressureForce::Monaghan1992, WallSums{}, nullptr, false, nullptr, path);
    return std::vector<std::vector<float>>{particles.ax, particles.ay, particles.az};
  };
  const auto scalar = accelerations(nullptr);
  ViscosityLanes path;
  path.lists = &lanes;
  const auto lanesPath = accelerations(&path);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(std::bit_cast<uint32_t>(lanesPath[c][i]), std::bit_cast<uint32_t>(scalar[c][i]))
          << "particle " << i << ", " << lists.count(i) << " neighbours, axis " << c;
  EXPECT_NE(scalar[0], std::vector<float>(n, 0.0f)) << "the viscosity moves something";
}

// Every path's sift finds the scalar path's list, in its order, for ranges of every length.
TEST(Sweeps, EveryPathSiftsTheSameNeighbours) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 3.0f);
  const size_t n = 300;
  std::vector<float> x(n), y(n), z(n);
  for (size_t j = 0; j < n; ++j) { x[j] = u(rng); y[j] = u(rng); z[j] = u(rng); }
  const std::array<std::array<uint32_t, 2>, 4> ranges = {{{0, 37}, {40, 41}, {50, 50}, {60, 300}}};
  for (SweepIsa isa : simdPaths())
    for (uint32_t self : {0u, 20u, 100u, 299u}) {
      std::vector<uint32_t> a(n), b(n);
      const auto& scalar = solvers::sweepTable(SweepIsa::Scalar);
      const size_t na =
          scalar.sift(x.data(), y.data(), z.data(), x[self], y[self], z[self], 1.0f, self, ranges.data(), 4, a.data());
      const size_t nb = solvers::sweepTable(isa).sift(x.data(), y.data(), z.data(), x[self], y[self], z[self], 1.0f,
                                                      self, ranges.data(), 4, b.data());
      ASSERT_EQ(na, nb) << solvers::sweepTable(isa).name;
      EXPECT_GT(na, 4u);
      a.resize(na);
      b.resize(nb);
      EXPECT_TRUE(a == b) << solvers::sweepTable(isa).name;
    }
}

// Whole runs: every path gives 1 and 2 threads the same floats, and each SIMD path's particles
// stay within kTolerance of the scalar path's (rounding, grown by the flow; about 1e-6 to 7e-6 m
// measured, on the dam breaks at 0.3 s and the body at 0.4 s).
constexpr double kTolerance = 1e-3;  // m, at a 0.5 m spacing

// The checks above for one scene run `seconds` on every path.
void expectPathsAgree(const SimParams& p, double seconds, bool thrown, const char* scene) {
  const auto scalar = run(p, "scalar", 1, seconds, thrown);
  EXPECT_TRUE(scalar == run(p, "scalar", 2, seconds, thrown)) << scene << ", scalar: 1 and 2 threads";
  for (SweepIsa isa : simdPaths()) {
    const char* name = solvers::sweepTable(isa).name;
    const auto one = run(p, name, 1, seconds, thrown);
    EXPECT_TRUE(one == run(p, name, 2, seconds, thrown)) << scene << ", " << name << ": 1 and 2 threads";
    const double d = largestDifference(one, scalar);
    EXPECT_LT(d, kTolerance) << scene << ", " << name;
    EXPECT_GT(d, 0.0) << scene << ", " << name << " is a path of its own";
    std::printf("%s, %s against scalar: %.3g m\n", scene, name, d);
  }
}

// The lanes path's runs are the scalar path's, bit for bit (DFSPH's sums and its viscosity pass
// run on it; IISPH keeps the scalar sums), on 1 and 2 threads.
TEST(Sweeps, LanesPathRunsAreTheScalarPathsBitForBit) {
  if (!solvers::sweepSupported(SweepIsa::Lanes)) GTEST_SKIP() << "this CPU runs no AVX2";
  const auto dam = run(damBreak("dfsph"), "scalar", 1, 0.3);
  EXPECT_TRUE(dam == run(damBreak("dfsph"), "lanes", 1, 0.3)) << "dam break, 1 thread";
  EXPECT_TRUE(dam == run(damBreak("dfsph"), "lanes", 2, 0.3)) << "dam break, 2 threads";
  const auto body = run(thrownAtABody(), "scalar", 2, 0.4, true);
  EXPECT_TRUE(body == run(thrownAtABody(), "lanes", 1, 0.4, true)) << "body as the boundary, 1 thread";
  EXPECT_TRUE(body == run(thrownAtABody(), "lanes", 2, 0.4, true)) << "body as the boundary, 2 threads";
}

// The same with the corrected kernel gradient (fluid.gradient_correction; the jellyfish's
// setting), whose sums run on the lane lists too.
TEST(Sweeps, LanesPathRunsWithTheCorrectedGradientAreTheScalarPathsBitForBit) {
  if (!solvers::sweepSupported(SweepIsa::Lanes)) GTEST_SKIP() << "this CPU runs no AVX2";
  SimParams damParams = damBreak("dfsph");
  damParams.fluid.gradientCorrection = true;
  {
    ForcePath force("lanes");
    Simulation sim(damParams);
    sim.advanceTo(0.01);
    EXPECT_NE(sim.solver().laneLists(), nullptr) << "the corrected gradient's sums on the lane lists";
  }
  const auto dam = run(damParams, "scalar", 1, 0.3);
  EXPECT_TRUE(dam == run(damParams, "lanes", 1, 0.3)) << "dam break, 1 thread";
  EXPECT_TRUE(dam == run(damParams, "lanes", 2, 0.3)) << "dam break, 2 threads";
  EXPECT_FALSE(dam == run(damBreak("dfsph"), "lanes", 2, 0.3)) << "the correction changes the run";
  SimParams bodyParams = thrownAtABody();
  bodyParams.fluid.gradientCorrection = true;
  const auto body = run(bodyParams, "scalar", 2, 0.4, true);
  EXPECT_TRUE(body == run(bodyParams, "lanes", 1, 0.4, true)) << "body as the boundary, 1 thread";
  EXPECT_TRUE(body == run(bodyParams, "lanes", 2, 0.4, true)) << "body as the boundary, 2 threads";
}

TEST(Sweeps, DamBreakOnEachPathMatchesTheScalarPath) { expectPathsAgree(damBreak("dfsph"), 0.3, false, "dam break"); }

TEST(Sweeps, IisphDamBreakOnEachPathMatchesTheScalarPath) {
  expectPathsAgree(damBreak("iisph"), 0.3, false, "iisph dam break");
}

TEST(Sweeps, BodyAsTheBoundaryOnEachPathMatchesTheScalarPath) {
  expectPathsAgree(thrownAtABody(), 0.4, true, "body as the boundary");
}
