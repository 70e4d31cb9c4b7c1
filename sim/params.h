// Simulation parameters as plain value types. Defaults are the paper's values (SPEC §2);
// pipeline/scene_params.h describes every field (JSON key, unit, valid range) for the scene
// loader and the JSON Schema, so the model itself stays free of any file format.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace kurage::sim {

enum class NegativePressure {
  Clamp,  // p = max(0, k (rho - rho0)): no tensile attraction at free surfaces (default)
  Keep,   // p = k (rho - rho0) as written in the paper, negative values kept
};

enum class WallSlip {
  NoSlip,    // the paper's wall: a particle that entered the wall is put back and stopped
  FreeSlip,  // put back, only the normal velocity component removed
};

enum class TimeStepMode { Fixed, Adaptive };

enum class PressureForce {
  Mueller2003,   // (5) as in the paper: -sum m_j (p_i + p_j) / (2 rho_j) grad W. It recovers only
                 // half of grad p in the interior, so a fluid at rest carries twice the physical
                 // pressure (docs/design/physics.md)
  Monaghan1992,  // -rho_i sum m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W: momentum-conserving and
                 // consistent (grad p of a linear field is recovered)
};

enum class WallDensity {
  None,        // the paper's walls: only the position clamp; particles near a wall miss kernel mass
  WallWeight,  // wall weight functions (Harada, Koshizuka & Kawaguchi 2007): the density and
               // pressure contributions of a virtual particle lattice behind each wall
  BoundaryParticles,  // wall samples with a volume psi (Akinci et al. 2012) that count in every
                      // density sum and push back with the particle's own pressure
                      // (sim/boundary_particles.h)
};

// How fluid blocks start (our choice, docs/design/physics.md "Hydrostatic start").
enum class InitialState {
  Lattice,      // every particle on the rest lattice with zero pressure: a column falls until its
                // pressure holds it (the paper's start)
  Hydrostatic,  // at rest in hydrostatic equilibrium: the solver's initial pressure is rho0 g depth
                // (PressureSolver::hydrostaticLattice and hydrostaticHead: DFSPH's warm start; WCSPH: the
                // lattice compressed to the density its equation of state needs for that pressure)
};

// Where fluid blocks' particles start, and the lattice the particle mass is calibrated on (ours;
// sim/packing.h, docs/design/physics.md "The packing").
enum class StartPacking {
  Lattice,  // the simple cubic lattice of spacing l; the mass gives a lattice particle rho0
  Relaxed,  // a relaxed, disordered tile of number density 1 / l^3 in blocks at least a tile's
            // edge on every axis (thinner blocks on the lattice); the mass gives the tile's mean
            // particle rho0, so the packing a still column settles into keeps its volume
};

class SolverParams;  // sim/solvers/pressure_solver.h

// fluid.solver: a pressure solver's name and its own parameters (sim/solvers/<name>/), a value
// (copies copy the parameters). A name not in pressureSolverNames() is std::invalid_argument.
class SolverChoice {
public:
  SolverChoice(const char* name = "wcsph");
  SolverChoice(const std::string& name);
  SolverChoice(const SolverChoice& other);
  SolverChoice(SolverChoice&& other) noexcept;
  SolverChoice& operator=(const SolverChoice& other);
  SolverChoice& operator=(SolverChoice&& other) noexcept;
  ~SolverChoice();

  const std::string& name() const { return name_; }
  SolverParams& params() { return *params_; }
  const SolverParams& params() const { return *params_; }
  // The parameters as the solver's own type (std::logic_error for another solver's).
  template <class P>
  P& as() {
    return const_cast<P&>(std::as_const(*this).template as<P>());
  }
  template <class P>
  const P& as() const {
    if (const P* p = dynamic_cast<const P*>(params_.get())) return *p;
    throw std::logic_error("fluid.solver is \"" + name_ + "\", not the solver of these parameters");
  }
  friend bool operator==(const SolverChoice& a, std::string_view name) { return a.name_ == name; }

private:
  std::string name_;
  std::unique_ptr<SolverParams> params_;
};

enum class DensitySum {
  Mass,    // (3) as in the paper: rho_i = sum_j m_j W_ij
  Volume,  // rho_i = rho0_i sum_j (m_j / rho0_j) W_ij: each neighbour counts by its rest volume, so a
           // particle at the interface of two phases (fluid and a body of another density or spacing)
           // sees its own rest density; identical to (3) within one phase
};

// The SPH kernels of the density sum and of the pressure gradient.
enum class SphKernel {
  Auto,         // the solver's own for the walls (PressureSolver::ownKernel: the cubic spline, but the
                // paper's for WCSPH without boundary-particle walls; docs/design/physics.md, "Walls under WCSPH")
  Mueller2003,  // the paper's: poly6 in the density sum (3), spiky in the pressure force (5) (WCSPH only)
  CubicSpline,  // one cubic spline for both, so the pressure force is the gradient of the density's energy
};

struct FluidParams {
  float spacing = 1.0f;             // l_avr, m (SPEC §2)
  float supportRadius = 1.5f;       // h / l_avr (SPEC §2: r_e = 1.5 l_avr)
  float restDensity = 1000.0f;      // rho0, kg/m^3
  float pressureStiffness = 2.2f;   // k_press, (m/s)^2
  float kinematicViscosity = 0.3f;  // nu, m^2/s
  NegativePressure negativePressure = NegativePressure::Clamp;
  PressureForce pressureForce = PressureForce::Mueller2003;
  // Correct each particle's kernel gradient with L_i = (sum_j V_j grad W_ij (x) (r_j - r_i))^-1
  // (Bonet & Lok 1999), so that the gradient of a linear pressure field is exact on any
  // neighbourhood: WCSPH's Monaghan1992 force, symmetrised as (L_i + L_j) / 2 (Mueller2003 has no
  // corrected form: a scene error), or DFSPH's density rate and push (sim/solvers/dfsph/dfsph.h).
  // Particles within h of a wall or with a degenerate neighbourhood (free surface) keep the plain
  // gradient.
  bool gradientCorrection = false;
  DensitySum densitySum = DensitySum::Mass;
  SphKernel kernel = SphKernel::Auto;  // resolved by resolvedKernel() before a simulation starts
  // The pressure solver and its parameters (sim/solvers/): "wcsph" (the paper's equation of state
  // (4)), "dfsph" (divergence-free SPH, Bender & Koschier 2015/2017), ... (pressureSolverNames()).
  SolverChoice solver;
  InitialState initialState = InitialState::Lattice;
  StartPacking packing = StartPacking::Lattice;

  float supportRadiusMetres() const { return supportRadius * spacing; }
  float speedOfSound() const { return std::sqrt(pressureStiffness); }  // m/s
};

struct ContainerParams {
  Eigen::Vector3f min{0, 0, 0};  // m
  Eigen::Vector3f max{10, 10, 10};
  WallSlip walls = WallSlip::NoSlip;
  WallDensity wallDensity = WallDensity::None;
};

// An axis-aligned block filled with fluid particles on a cubic lattice of the fluid spacing,
// the first particle half a spacing inside `min`.
struct FluidBlock {
  Eigen::Vector3f min{0, 0, 0};
  Eigen::Vector3f max{1, 1, 1};
};

// A nozzle (the jellyfish's faucets, SPEC §4.3): a disc of `radius` at `position`, facing
// `direction`, that emits fluid at `speed` from `start` to `end`. Particles are spawned in
// layers one fluid spacing apart, each layer a sunflower (Vogel) pattern of the disc whose count
// keeps the emitted volume equal to area x speed x time to within one particle per layer and half
// a layer in all (the last layer is rounded).
struct EmitterParams {
  Eigen::Vector3f position{0, 0, 0};   // m, centre of the nozzle disc
  Eigen::Vector3f direction{1, 0, 0};  // outflow direction (normalised on use)
  float radius = 1.0f;                 // m
  float speed = 2.0f;                  // m/s
  float start = 0.0f;                  // s
  float end = 1.0f;                    // s
};

// A region that removes the fluid particles that enter it (an outflow).
struct SinkParams {
  Eigen::Vector3f min{0, 0, 0};
  Eigen::Vector3f max{1, 1, 1};
};

struct TimeStepParams {
  TimeStepMode mode = TimeStepMode::Adaptive;
  float fixedStep = 0.01f;  // s, used when mode == Fixed
  float cflFactor = 0.4f;   // dt <= cfl * h / (c + |v|max)
  float viscousFactor = 0.125f;  // dt <= factor * h^2 / nu
  float forceFactor = 0.25f;     // dt <= factor * sqrt(h / |a|max)
  float springFactor = 0.5f;  // dt <= factor * min_i min(sqrt(2 m_i / K_i), m_i / D_i) (bodies only)
  float pressureFactor = 0.4f;  // dt <= factor * l / sqrt(|g| H) (incompressible solvers; time_step.h)
  float maxStep = 0.05f;    // s, upper limit of the adaptive step
  float minStep = 1e-5f;    // s, floor: a smaller bound stops the run with an error
};

// ---- Telescopic deformable bodies (SPEC §3) ----

enum class BodyShape {
  Box,       // a filled block: lattice points of the body spacing in [min, max]
  Membrane,  // a sheet over [min, max] in x and y, `layers` lattice layers centred on (min.z + max.z) / 2
  Shell,     // a spherical cap (jellyfish bell): `layers` concentric shells, the innermost at inner_radius
  Chain,     // a line of particles from `start` to `end` (oral arms), hung from another body
};

// Particles (pins) or springs (muscles) of a body picked by name or by region.
enum class SelectionKind {
  All,     // the whole body
  Rim,     // the edge band of a membrane or shell (rim_width body spacings wide); a chain's first particle
  Region,  // particles inside the box [min, max] at t = 0 (springs: both ends inside)
};

struct Selection {
  SelectionKind kind = SelectionKind::Region;
  Eigen::Vector3f min{0, 0, 0};
  Eigen::Vector3f max{0, 0, 0};
  float width = 0.0f;  // 'rim': band width in body spacings (0 = the body's rim_width)
};

// Particles of a body with their own specific gravity (a bottom-heavy bell, a weighted rim): the
// body's specific_gravity holds for the rest; where parts overlap the later one wins.
struct BodyPart {
  std::string name = "part";
  Selection particles{SelectionKind::Rim, {0, 0, 0}, {0, 0, 0}};
  float specificGravity = 1.0f;
};

// A muscle's force per spring over time (N, positive pulls the spring's ends together).
enum class CurveType { Keys, Pulse };
struct CurveKey {
  float time = 0.0f;   // s
  float value = 0.0f;  // N
};
struct ForceCurve {
  CurveType type = CurveType::Keys;
  std::vector<CurveKey> keys;  // piecewise linear, constant before the first and after the last key
  float period = 1.0f;         // pulse train: s
  float duty = 0.5f;           // fraction of the period the force is on
  float amplitude = 1.0f;      // N
  float ramp = 0.0f;           // s to rise from 0 to the amplitude and to fall back (within the on time)
  float start = 0.0f;          // s, first pulse
  float end = 1e30f;           // s, no pulse starts at or after this time

  float at(double t) const;
};

struct MuscleParams {
  std::string name = "muscle";
  Selection springs{SelectionKind::All, {0, 0, 0}, {0, 0, 0}};
  ForceCurve force;
  // Righting reflex (ours, after the statocysts of medusae): the force on each spring is scaled by
  // 1 - gain h, h the height of its ends above the ring's centre across the body's axis, over the
  // ring's radius (h = -sin(tilt) on the lowest side of a tilted ring, 0 all round when level), so a
  // tilted body contracts its lower side harder. 0 = off.
  float righting = 0.0f;
  // Depth reflex (ours, a medusa's gravity sense keeping it below the surface): the force fades
  // linearly to zero as the body's centroid rises from `ceiling - ceilingBand` to `ceiling` (height
  // against gravity, m). Off when ceilingBand is 0.
  float ceiling = 0.0f;
  float ceilingBand = 0.0f;
  // The reflex anticipates: it acts on the height the centroid will reach in this many seconds at
  // its present vertical speed (z + lead v), so that a bell climbing fast eases off early.
  float ceilingLead = 0.0f;
};

// The depth reflex's factor at a centroid height z: 1 below the band, 0 above the ceiling.
inline float ceilingFactor(float ceiling, float band, double z) {
  if (!(band > 0.0f)) return 1.0f;
  return float(std::clamp((double(ceiling) - z) / double(band), 0.0, 1.0));
}

// How a body's particles meet an incompressible solver's pressure (ours; docs/design/physics.md, "Bodies
// as the fluid's boundary").
enum class BodyCoupling {
  Solved,    // unknowns of the solves with their own rest density (10), as the paper's weak
             // coupling computes body particles like fluid ones
  Boundary,  // DFSPH: no unknowns; the fluid meets them as boundary samples of volume m_i / rho0_i
             // (Akinci et al. 2012, with (10)'s telescopic volume), and each one's pressure reaction
             // is spread over its spring patch (sim/solvers/dfsph/dfsph.h)
};

// What the rest density (10) follows (SPEC §3.3).
enum class TelescopicMeasure {
  Isotropic,    // the paper's (8): every spring's length ratio, shortened springs raise rho0
  StretchOnly,  // ours: min(1, (8)) -- stretch lowers rho0 as in the paper, shortening leaves it:
                // for a wall whose muscle shortens it in one direction while it keeps its volume
                // (docs/design/physics.md, The jellyfish)
};

enum class Damper {
  Implicit,  // (7)'s damper on the relative velocity along each spring, solved exactly per spring (any step)
  Explicit,  // (7) as written: upwind length change, explicit (the step must stay below m / sum d)
};

struct BodyParams {
  std::string name = "body";
  BodyShape shape = BodyShape::Box;
  Eigen::Vector3f min{0, 0, 0};  // box, membrane
  Eigen::Vector3f max{1, 1, 1};
  int layers = 3;                   // membrane, shell
  Eigen::Vector3f center{0, 0, 0};  // shell: centre of the spheres
  Eigen::Vector3f axis{0, 0, 1};    // shell: from the centre through the apex
  float innerRadius = 2.0f;         // shell, m: radius of the innermost layer
  float openingAngle = 90.0f;       // shell: polar angle of the rim from the apex, degrees (90 = hemisphere)
  Eigen::Vector3f start{0, 0, 0};   // chain
  Eigen::Vector3f end{0, 0, 1};
  std::string attachTo;             // chain: the body whose particles near the chain's start hold it
  float spacing = 0.5f;             // body particle spacing (diameter) / l_avr (SPEC §3.2, paper 0.5)
  float specificGravity = 1.1f;     // rho0_body / 1000 kg/m^3
  float stiffness = 30.0f;          // k, N/m (SPEC §5: 30 membrane, 10 box, 50 jellyfish; docs/design/physics.md)
  float damping = 10.0f;            // d, N s/m (SPEC §5: 10, 15, 10)
  float connectionRadius = 2.1f;    // h_spr / l_avr
  Damper damper = Damper::Implicit;
  bool telescopicDensity = true;    // (8)-(10); false = the paper's "conventional mass-spring model"
  TelescopicMeasure telescopicMeasure = TelescopicMeasure::Isotropic;
  BodyCoupling coupling = BodyCoupling::Solved;
  // Chain: bending stiffness k_b (ours, N/m): each inner particle i feels k_b L_i and its two
  // neighbours -k_b L_i / 2 each, L_i = x_{i-1} - 2 x_i + x_{i+1} (the gradient of the energy
  // k_b / 4 sum |L_i|^2, zero on a straight chain; momentum-conserving). 0 = off (the paper).
  float bending = 0.0f;
  // Scale of collisions.fluidContact for this body's particles (1 = the scene's, 0 = none: a chain
  // has no wall to keep fluid out of, and the void the contact clears round a lone line of
  // particles is squeezed by the water's pressure until its particles pair up).
  float fluidContactScale = 1.0f;
  float rimWidth = 1.0f;            // rim band width in body spacings
  std::vector<Selection> pins;      // particles held fixed in space
  float holdUntil = 0.0f;           // s: the whole body is held where it was built until then
  std::vector<MuscleParams> muscles;
  std::vector<BodyPart> parts;      // particles with their own specific gravity

  float spacingMetres(float fluidSpacing) const { return spacing * fluidSpacing; }
  float restDensity() const { return 1000.0f * specificGravity; }
};

// Collisions between body particles not joined by a spring (SPEC §3.4).
struct CollisionParams {
  int maxPasses = 32;  // cap of the collision loop
  // Fluid particles closer than this many (current) body diameters to a body particle are pushed
  // out in the same loop (ours, not the paper's: 0 = off). 1 keeps fluid out of the gaps of a
  // body's particle lattice, which a smooth SPH pressure alone does not (docs/design/physics.md).
  float fluidContact = 0.0f;
};

struct SimParams {
  FluidParams fluid;
  Eigen::Vector3f gravity{0.0f, 0.0f, -6.0f};  // m/s^2 (SPEC §2: g = 6.0)
  ContainerParams container;
  std::vector<FluidBlock> fluidBlocks;
  std::vector<EmitterParams> emitters;
  std::vector<SinkParams> sinks;
  std::vector<BodyParams> bodies;
  CollisionParams collisions;
  TimeStepParams timeStep;
};

}  // namespace kurage::sim
