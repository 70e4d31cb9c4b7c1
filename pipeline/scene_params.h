// The parameter registry: for every component of a scene, its JSON keys, units, documentation
// and valid ranges, next to the struct it fills. Defaults are the structs' own initial values
// (sim/params.h holds the paper's, SPEC §2). Used only through the visitors of
// pipeline/param_visitor.h; include it in .cpp files only.
#pragma once

#include "pipeline/param_visitor.h"
#include "pipeline/scene.h"
#include "sim/solvers/pressure_solver.h"

namespace kurage::pipeline {

inline const EnumTable<sim::NegativePressure> kNegativePressure{{"clamp", sim::NegativePressure::Clamp},
                                                                {"keep", sim::NegativePressure::Keep}};
inline const EnumTable<sim::WallSlip> kWallSlip{{"no_slip", sim::WallSlip::NoSlip},
                                                {"free_slip", sim::WallSlip::FreeSlip}};
inline const EnumTable<sim::PressureForce> kPressureForce{{"mueller2003", sim::PressureForce::Mueller2003},
                                                          {"monaghan1992", sim::PressureForce::Monaghan1992}};
inline const EnumTable<sim::DensitySum> kDensitySum{{"mass", sim::DensitySum::Mass}, {"volume", sim::DensitySum::Volume}};
inline const EnumTable<sim::WallDensity> kWallDensity{{"none", sim::WallDensity::None},
                                                      {"wall_weight", sim::WallDensity::WallWeight},
                                                      {"boundary_particles", sim::WallDensity::BoundaryParticles}};
inline const EnumTable<sim::SphKernel> kSphKernel{{"auto", sim::SphKernel::Auto},
                                                  {"mueller2003", sim::SphKernel::Mueller2003},
                                                  {"cubic_spline", sim::SphKernel::CubicSpline}};
inline const EnumTable<sim::InitialState> kInitialState{{"lattice", sim::InitialState::Lattice},
                                                        {"hydrostatic", sim::InitialState::Hydrostatic}};
inline const EnumTable<sim::StartPacking> kStartPacking{{"lattice", sim::StartPacking::Lattice},
                                                       {"relaxed", sim::StartPacking::Relaxed}};
// The pressure solvers' names and their documentation come from their registry
// (sim/solvers/registry.cpp), their parameters from their own describe() (sim/solvers/<name>/).
inline const EnumTable<std::string>& solverTable() {
  static const EnumTable<std::string> table = [] {
    EnumTable<std::string> t;
    for (const std::string& name : sim::pressureSolverNames()) t.emplace_back(name.c_str(), name);
    return t;
  }();
  return table;
}
inline const char* solverDoc() {
  static const std::string doc = [] {
    const std::vector<std::string>& summaries = sim::pressureSolverSummaries();
    std::string d = "pressure solver: ";
    for (size_t k = 0; k < summaries.size(); ++k)
      d += (k == 0 ? "" : k + 1 == summaries.size() ? " or " : ", ") + summaries[k];
    return d;
  }();
  return doc.c_str();
}
// The scene's solver's parameters (keys of `fluid`); the schema has every solver's.
template <class V>
void describeSolverParams(V& v, sim::SolverChoice& solver) {
  SimParamVisitor<V> adapter(v);
  solver.params().describe(adapter);
}
inline void describeSolverParams(SchemaWriter& v, sim::SolverChoice&) {
  SimParamVisitor<SchemaWriter> adapter(v);
  for (const std::string& name : sim::pressureSolverNames()) sim::makeSolverParams(name)->describe(adapter);
}
inline const EnumTable<sim::TimeStepMode> kTimeStepMode{{"fixed", sim::TimeStepMode::Fixed},
                                                        {"adaptive", sim::TimeStepMode::Adaptive}};

template <class V>
void describe(V& v, sim::FluidParams& p) {
  v.value("spacing", p.spacing, {"m", "initial mean particle spacing l_avr (paper: 1.0)", positive()});
  v.value("support_radius", p.supportRadius,
          {"l_avr", "SPH support (influence) radius h = r_e in units of the spacing (paper: 1.5)", between(1.0, 4.0)});
  v.value("density", p.restDensity, {"kg/m^3", "rest density rho0 of the fluid (paper: 1000)", positive()});
  v.value("pressure_stiffness", p.pressureStiffness,
          {"(m/s)^2", "pressure coefficient k_press in p = k (rho - rho0); speed of sound c = sqrt(k) (paper: 2.2)",
           positive()});
  v.value("viscosity", p.kinematicViscosity,
          {"m^2/s", "kinematic viscosity nu; mu = rho0 nu (paper: 0.3)", nonNegative()});
  v.enumeration("negative_pressure", p.negativePressure, kNegativePressure,
                {"", "'clamp' sets p = max(0, k (rho - rho0)) so that free surfaces, where a particle has fewer "
                     "neighbours than at rest, do not pull particles into clumps (tensile instability); 'keep' "
                     "uses the paper's p = k (rho - rho0) unchanged"});
  v.enumeration("pressure_force", p.pressureForce, kPressureForce,
                {"", "'mueller2003': the paper's (5), -sum m_j (p_i + p_j) / (2 rho_j) grad W, which recovers only "
                     "half of grad p (a fluid at rest carries about twice the physical pressure); 'monaghan1992': "
                     "-rho_i sum m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W, consistent and momentum-conserving"});
  v.enumeration("density_sum", p.densitySum, kDensitySum,
                {"", "'mass': the paper's (3), rho_i = sum m_j W; 'volume': rho_i = rho0_i sum (m_j / rho0_j) W, the "
                     "same within one phase, but a particle at the interface of a fluid and a body of another "
                     "density or spacing sees its own rest density instead of a spurious pressure "
                     "(docs/design/physics.md)"});
  v.enumeration("kernel", p.kernel, kSphKernel,
                {"", "the SPH kernels: 'mueller2003' (the paper's: poly6 in the density sum, spiky in the pressure "
                     "force; wcsph only), 'cubic_spline' (one cubic spline for both, so the pressure force is the "
                     "gradient of the density's energy), or 'auto': the solver's own (cubic_spline; wcsph: mueller2003, "
                     "but cubic_spline with boundary_particles walls, where the paper's pair let a still tank gain "
                     "energy, docs/design/physics.md)"});
  std::string solver = p.solver.name();
  v.enumeration("solver", solver, solverTable(), {"", solverDoc()});
  if (solver != p.solver.name()) p.solver = sim::SolverChoice(solver);  // read from the scene
  describeSolverParams(v, p.solver);
  v.enumeration("initial_state", p.initialState, kInitialState,
                {"", "'lattice': fluid blocks start on the rest lattice without pressure, so a column falls until "
                     "its pressure holds it; 'hydrostatic': they start at rest in hydrostatic equilibrium "
                     "(a solver that keeps its pressure from step to step starts from rho0 g depth; wcsph: the "
                     "lattice is compressed to the density whose pressure carries the column)"});
  v.enumeration("packing", p.packing, kStartPacking,
                {"", "'lattice': fluid blocks start on the simple cubic lattice, the particle mass calibrated on it; "
                     "'relaxed': blocks at least 8 spacings (and 2 h + 2 l) on every axis start on a relaxed, "
                     "disordered packing of the same number density, the mass calibrated on it, so that a still "
                     "column does not lose volume (about 0.35 % of a 20 m column in 30 s on the lattice) as its "
                     "lattice rearranges (cubic-spline density kernel only; docs/design/physics.md)"});
  v.value("gradient_correction", p.gradientCorrection,
          {"", "correct each particle's kernel gradient (Bonet & Lok 1999) so that a linear pressure field's "
               "gradient is exact on a disordered neighbourhood: WCSPH's force with 'monaghan1992', or DFSPH's "
               "push and density rate (about 1.4 times the cost of a DFSPH step); particles within h of a wall "
               "or at a free surface keep the plain gradient"});
}

template <class V>
void describe(V& v, sim::ContainerParams& p) {
  v.value("min", p.min, {"m", "lower corner of the box that holds everything", anyValue(), true});
  v.value("max", p.max, {"m", "upper corner of the box", anyValue(), true});
  v.enumeration("walls", p.walls, kWallSlip,
                {"", "'no_slip' (the paper): a particle that enters a wall is put back on it and stopped; "
                     "'free_slip': put back, only the velocity into the wall removed"});
  v.enumeration("wall_density", p.wallDensity, kWallDensity,
                {"", "'none' (the paper): walls only clamp positions, so particles near a wall miss kernel mass and "
                     "crowd against it; 'wall_weight': walls add the density and pressure of a virtual particle "
                     "lattice behind them (Harada, Koshizuka & Kawaguchi 2007), tabulated with the fluid's kernels, "
                     "and keep particle centres half a spacing inside, for both solvers; 'boundary_particles': the walls are sampled by static particles continuing "
                     "the fluid's lattice that count in every density sum and push back with each particle's own "
                     "pressure (Akinci et al. 2012), for both solvers"});
}

template <class V>
void describe(V& v, sim::FluidBlock& p) {
  v.value("min", p.min, {"m", "lower corner; particles start half a spacing inside", anyValue(), true});
  v.value("max", p.max, {"m", "upper corner", anyValue(), true});
}

template <class V>
void describe(V& v, sim::EmitterParams& p) {
  v.value("position", p.position, {"m", "centre of the nozzle disc", anyValue(), true});
  v.value("direction", p.direction, {"", "outflow direction (need not be unit length)", anyValue(), true});
  v.value("radius", p.radius, {"m", "nozzle radius", positive(), true});
  v.value("speed", p.speed, {"m/s", "outflow speed", positive(), true});
  v.value("start", p.start, {"s", "time the nozzle opens", nonNegative()});
  v.value("end", p.end, {"s", "time the nozzle closes", nonNegative(), true});
}

template <class V>
void describe(V& v, sim::SinkParams& p) {
  v.value("min", p.min, {"m", "lower corner of the outflow box", anyValue(), true});
  v.value("max", p.max, {"m", "upper corner of the outflow box", anyValue(), true});
}

inline const EnumTable<sim::BodyShape> kBodyShape{{"box", sim::BodyShape::Box},
                                                  {"membrane", sim::BodyShape::Membrane},
                                                  {"shell", sim::BodyShape::Shell},
                                                  {"chain", sim::BodyShape::Chain}};
inline const EnumTable<sim::SelectionKind> kSelectionKind{{"all", sim::SelectionKind::All},
                                                          {"rim", sim::SelectionKind::Rim},
                                                          {"region", sim::SelectionKind::Region}};
inline const EnumTable<sim::BodyCoupling> kBodyCoupling{{"solved", sim::BodyCoupling::Solved},
                                                       {"boundary", sim::BodyCoupling::Boundary}};
inline const EnumTable<sim::TelescopicMeasure> kTelescopicMeasure{{"isotropic", sim::TelescopicMeasure::Isotropic},
                                                                   {"stretch_only", sim::TelescopicMeasure::StretchOnly}};
inline const EnumTable<sim::Damper> kDamper{{"implicit", sim::Damper::Implicit}, {"explicit", sim::Damper::Explicit}};
inline const EnumTable<sim::CurveType> kCurveType{{"keys", sim::CurveType::Keys}, {"pulse", sim::CurveType::Pulse}};

template <class V>
void describe(V& v, sim::Selection& p) {
  v.enumeration("select", p.kind, kSelectionKind,
                {"", "'all' the whole body, 'rim' the edge band of a membrane or shell (a chain's first particle), "
                     "'region' the box [min, max] at t = 0", {}, true});
  v.value("min", p.min, {"m", "lower corner of the region (select = 'region')"});
  v.value("max", p.max, {"m", "upper corner of the region"});
  v.value("width", p.width,
          {"spacings", "select = 'rim': width of the band from the edge (0 = the body's rim_width)", nonNegative()});
}

template <class V>
void describe(V& v, sim::BodyPart& p) {
  v.value("name", p.name, {"", "part name"});
  v.object("particles", p.particles, {"", "its particles ('all', 'rim' or a region)", {}, true});
  v.value("specific_gravity", p.specificGravity,
          {"", "rest density / 1000 kg/m^3 of these particles (the body's specific_gravity holds for the rest)",
           positive(), true});
}

template <class V>
void describe(V& v, sim::CurveKey& p) {
  v.value("time", p.time, {"s", "time of the key", nonNegative(), true});
  v.value("force", p.value, {"N", "force per spring at that time; positive contracts", anyValue(), true});
}

template <class V>
void describe(V& v, sim::ForceCurve& p) {
  v.enumeration("type", p.type, kCurveType,
                {"", "'keys': piecewise linear between keys (constant outside); 'pulse': a pulse train", {}, true});
  v.list("keys", p.keys, {"", "the keys of a 'keys' curve, by increasing time"});
  v.value("period", p.period, {"s", "pulse period", positive()});
  v.value("duty", p.duty, {"", "fraction of each period the pulse is on", {0.0, 1.0, false, true}});
  v.value("amplitude", p.amplitude, {"N", "pulse force per spring; positive contracts, negative expands"});
  v.value("ramp", p.ramp, {"s", "rise and fall time of each pulse (smooth onset avoids shocks)", nonNegative()});
  v.value("start", p.start, {"s", "time of the first pulse", nonNegative()});
  v.value("end", p.end, {"s", "no pulse starts at or after this time", nonNegative()});
}

template <class V>
void describe(V& v, sim::MuscleParams& p) {
  v.value("name", p.name, {"", "muscle name (reported in run.json)"});
  v.object("springs", p.springs,
           {"", "the springs it pulls: those whose both ends are selected ('all', 'rim' or a region)", {}, true});
  v.object("force", p.force, {"", "force per spring against time (N): positive pulls the ends together", {}, true});
  v.value("righting", p.righting,
          {"", "righting reflex gain (ours, after a medusa's statocysts): each spring's force is scaled by 1 - gain h, "
               "h its ends' height above the ring's centre across the body's axis over the ring's radius, so a tilted "
               "body contracts its lower side harder (0 = off)", between(0.0, 100.0)});
  v.value("ceiling", p.ceiling,
          {"m", "depth reflex (ours, a medusa's gravity sense): the force fades linearly to zero as the body's centroid "
                "rises through the ceiling_band below this height (measured against gravity)", anyValue()});
  v.value("ceiling_band", p.ceilingBand,
          {"m", "depth reflex: the height over which the force fades below the ceiling (0 = no depth reflex)",
           nonNegative()});
  v.value("ceiling_lead", p.ceilingLead,
          {"s", "depth reflex: it acts on the centroid's height this far ahead at its present vertical speed "
                "(z + lead v), so that a fast climb eases off early (0 = the height now)", between(0.0, 100.0)});
}

template <class V>
void describe(V& v, sim::BodyParams& p) {
  v.value("name", p.name, {"", "body name, unique in the scene (chains refer to it)"});
  v.enumeration("shape", p.shape, kBodyShape,
                {"", "'box' (filled block), 'membrane' (sheet of `layers` layers in x-y), 'shell' (spherical cap "
                     "of `layers` layers: a jellyfish bell) or 'chain' (a line of particles: an oral arm)", {}, true});
  v.value("min", p.min, {"m", "box: lower corner; membrane: corner of the sheet (its layers are centred on (min.z + max.z) / 2)"});
  v.value("max", p.max, {"m", "box, membrane: upper corner"});
  v.value("layers", p.layers, {"", "membrane, shell: number of particle layers", between(1, 64)});
  v.value("center", p.center, {"m", "shell: centre of the spheres"});
  v.value("axis", p.axis, {"", "shell: direction from the centre through the apex"});
  v.value("inner_radius", p.innerRadius, {"m", "shell: radius of the innermost layer", positive()});
  v.value("opening_angle", p.openingAngle,
          {"deg", "shell: polar angle of the rim from the apex (90 = hemisphere)", {0.0, 180.0, false, true}});
  v.value("start", p.start, {"m", "chain: first particle (where it hangs)"});
  v.value("end", p.end, {"m", "chain: direction and length"});
  v.value("attach_to", p.attachTo,
          {"", "chain: name of the body whose particles within the connection radius of the start hold the chain"});
  v.value("spacing", p.spacing,
          {"l_avr", "particle spacing (diameter) as a fraction of the fluid's (paper: 0.5; a body expected to stretch n "
                    "times should use 1/n)", {0.0, 4.0, false, true}});
  v.value("specific_gravity", p.specificGravity,
          {"", "initial rest density / 1000 kg/m^3 (paper: 1.1 membrane and jellyfish, 0.7 box)", positive()});
  v.value("stiffness", p.stiffness,
          {"N/m", "spring coefficient k of (7) (paper: 30 membrane, 10 box, 50 jellyfish; scenes/box.json explains "
                  "why it uses 1000 times the paper's value)", nonNegative()});
  v.value("damping", p.damping, {"N s/m", "damper coefficient d of (7) (paper: 10, 15, 10)", nonNegative()});
  v.enumeration("damper", p.damper, kDamper,
                {"", "'implicit': each spring's damper decays its ends' relative velocity along it exactly over the step, so it never bounds the time "
                     "step; 'explicit': (7) as written with the upwind length change (step < m / sum d)"});
  v.value("connection_radius", p.connectionRadius,
          {"l_avr", "h_spr: every pair closer than this at t = 0 is joined by a spring (paper: 2.1, 2.4, 4.1)", positive()});
  v.value("telescopic_density", p.telescopicDensity,
          {"", "rest density follows stretch, (8)-(10); false = the paper's conventional mass-spring model"});
  v.enumeration("telescopic_measure", p.telescopicMeasure, kTelescopicMeasure,
                {"", "what the rest density follows: 'isotropic' = the paper's (8), every spring's length ratio, so a "
                     "shortened spring raises it; 'stretch_only' (ours) = min(1, (8)): a stretch lowers it as in the "
                     "paper, a shortening leaves it (a wall that a ring muscle shortens in one direction keeps its "
                     "volume; docs/design/physics.md 'The jellyfish')"});
  v.enumeration("coupling", p.coupling, kBodyCoupling,
                {"", "how the fluid's pressure meets the body: 'solved' = its particles are unknowns of the pressure "
                     "solves with their own rest density, like fluid particles (the paper's coupling); 'boundary' "
                     "(ours, dfsph) = the fluid meets them as boundary samples whose volume m / rho0 grows with (10), "
                     "and each one's share of the pressure is spread over its spring neighbours (docs/design/physics.md "
                     "'Bodies as the fluid's boundary')"});
  v.value("bending", p.bending,
          {"N/m", "chain: bending stiffness (ours): each particle is pulled toward the line through its two neighbours "
                  "with bending x (x_prev - 2 x + x_next), the neighbours take the reaction (0 = off, the paper's chains)",
           nonNegative()});
  v.value("fluid_contact_scale", p.fluidContactScale,
          {"", "this body's share of collisions.fluid_contact (1 = the scene's, 0 = no fluid contact: chains, whose "
               "lone line of particles the water squeezes together through the void the contact clears)",
           between(0.0, 100.0)});
  v.value("rim_width", p.rimWidth, {"spacings", "width of the 'rim' selection band", positive()});
  v.list("pins", p.pins, {"", "particles held fixed in space ('rim' or a region)"});
  v.value("hold_until", p.holdUntil,
          {"s", "the whole body is held where it was built, at rest, until this time: the fluid settles "
                "around it first (0 = free from the start)", nonNegative()});
  v.list("muscles", p.muscles, {"", "named groups of springs driven by a force curve"});
  v.list("parts", p.parts,
         {"", "particles with their own specific gravity (a bottom-heavy bell: a heavier margin); where parts "
              "overlap the later one wins"});
}

template <class V>
void describe(V& v, sim::CollisionParams& p) {
  v.value("max_passes", p.maxPasses,
          {"", "cap of the body collision loop per step (repeated until a pass finds no collision); run.json "
               "reports how often it was hit", between(1, 100000)});
  v.value("fluid_contact", p.fluidContact,
          {"body diameters", "fluid particles closer than this to a body particle are pushed out in the same loop "
                             "(not in the paper; 0 = off): 1 keeps fluid out of a body's particle lattice",
           between(0.0, 4.0)});
}

template <class V>
void describe(V& v, sim::TimeStepParams& p) {
  v.enumeration("mode", p.mode, kTimeStepMode, {"", "'adaptive' (bounded by CFL, viscosity, force) or 'fixed'"});
  v.value("fixed_step", p.fixedStep, {"s", "the step when mode is 'fixed'", positive()});
  v.value("cfl", p.cflFactor, {"", "CFL factor: dt <= cfl h / (c + |v|max)", {0.0, 1.0, true, false}});
  v.value("viscous_factor", p.viscousFactor, {"", "dt <= factor h^2 / nu", {0.0, 1.0, true, false}});
  v.value("force_factor", p.forceFactor, {"", "dt <= factor sqrt(h / |a|max)", {0.0, 1.0, true, false}});
  v.value("spring_factor", p.springFactor,
          {"", "bodies: dt <= factor min_i min(sqrt(2 m_i / K_i), m_i / D_i), K_i and D_i the sums of k and d over "
               "particle i's springs", {0.0, 2.0, true, false}});
  v.value("pressure_factor", p.pressureFactor,
          {"", "incompressible solvers: dt <= factor l / sqrt(|g| H), H the fluid's depth: the explicit "
               "oscillation of a particle among its neighbours under the hydrostatic pressure (docs/design/physics.md)",
           {0.0, 2.0, true, false}});
  v.value("max_step", p.maxStep, {"s", "largest adaptive step", positive()});
  v.value("min_step", p.minStep, {"s", "floor of the adaptive step: a bound below it stops the run", positive()});
}

template <class V>
void describe(V& v, ExportSelection& p) {
  v.value("mesh_ply", p.meshPly, {"", "each surface (fluid, each body) as binary PLY with normals: exports/GRID/NNNN.ply"});
  v.value("mesh_obj", p.meshObj, {"", "each surface as Wavefront OBJ: exports/GRID/NNNN.obj"});
  v.value("particles_vtp", p.particlesVtp,
          {"", "particles as VTK XML PolyData with every attribute: exports/particles/NNNN.vtp and particles.pvd"});
  v.value("particles_ply", p.particlesPly, {"", "particles as binary PLY with every attribute: exports/particles/NNNN.ply"});
  v.value("chains_vtp", p.chainsVtp, {"", "chains (oral arms) as VTK polylines: exports/chains/NNNN.vtp and chains.pvd"});
  v.value("chains_obj", p.chainsObj, {"", "chains as OBJ polylines: exports/chains/NNNN.obj"});
}

template <class V>
void describe(V& v, OutputParams& p) {
  v.value("duration", p.duration, {"s", "simulated time; frames from t = 0 to t = duration", positive(), true});
  v.value("fps", p.fps, {"1/s", "output frames per second of simulated time", {0.0, 1000.0, true, false}});
  v.object("exports", p.exports, {"", "files for other tools, made per frame after the surfaces (kurage export)"});
}

inline const EnumTable<render::MetaballKernel> kMetaballKernel{{"isotropic", render::MetaballKernel::Isotropic},
                                                              {"anisotropic", render::MetaballKernel::Anisotropic}};

template <class V>
void describe(V& v, render::AnisotropyParams& p) {
  v.value("neighbour_radius", p.neighbourRadius,
          {"R", "radius of the neighbourhood whose spread shapes a particle's ellipsoid, in units of the field radius",
           between(0.25, 4.0)});
  v.value("max_stretch", p.maxStretch,
          {"", "longest over shortest axis of an ellipsoid at most (Yu & Turk's k_r)", between(1.0, 16.0)});
  v.value("min_neighbours", p.minNeighbours,
          {"", "a particle with fewer neighbours (itself included) keeps the sphere of radius R", between(1, 1000)});
  v.value("smoothing", p.smoothing,
          {"", "how far each blob's centre moves towards its neighbours' weighted mean (Yu & Turk's lambda; 0 keeps "
               "the particles' positions)",
           between(0.0, 1.0)});
}

template <class V>
void describe(V& v, render::MetaballParams& p) {
  v.value("radius", p.radius, {"m", "field radius R of each particle's blob s (1 - (r/R)^2)^2", positive()});
  v.value("threshold", p.threshold, {"", "the surface is where the summed field equals this", positive()});
  v.value("strength", p.strength, {"", "blob strength s (POV-Ray's component strength)", positive()});
  v.value("voxel_size", p.voxelSize, {"m", "level set voxel size", positive()});
  v.value("half_width", p.halfWidth, {"voxels", "narrow band half width", between(2.0, 10.0)});
  v.enumeration("kernel", p.kernel, kMetaballKernel,
                {"", "'isotropic': every particle's blob is a sphere of radius R (POV-Ray's blobs); 'anisotropic': an "
                     "ellipsoid, longest axis R, that follows the spread of the particle's neighbours (Yu & Turk 2013), "
                     "so that a sheet of particles gives a thin wall and a flat surface stays flat (docs/design/rendering.md)"});
  v.object("anisotropy", p.anisotropy, {"", "the ellipsoids of 'anisotropic' kernels"});
}

template <class V>
void describe(V& v, render::AirborneParams& p) {
  v.value("enabled", p.enabled, {"", "give fast, sparse fluid particles (a falling jet, spray) a smaller blob"});
  v.value("radius", p.radius, {"m", "blob radius of a fully airborne particle (at most surface.fluid.radius when enabled)", positive()});
  v.value("speed_min", p.speedMin, {"m/s", "slower particles keep surface.fluid.radius", nonNegative()});
  v.value("speed_full", p.speedFull, {"m/s", "faster particles are fully fast (above speed_min)", positive()});
  v.value("fill_full", p.fillFull,
          {"", "particles whose neighbours within R fill less than this fraction of a full sphere are fully sparse",
           nonNegative()});
  v.value("fill_min", p.fillMin, {"", "denser particles keep surface.fluid.radius (above fill_full)", positive()});
}

template <class V>
void describe(V& v, SurfaceParams& p) {
  v.object("fluid", p.fluid, {"", "metaball surface of the fluid particles"});
  v.object("airborne", p.airborne,
           {"", "smaller blobs for the fluid's fast, sparse particles, so that a jet reads as a stream "
                "(render/airborne.h: radius R - w (R - radius), w = fast x sparse, each a linear ramp)"});
  v.object("bodies", p.bodies, {"", "metaball surface of each body (chains excepted), one grid per body name"});
  v.value("clip_to_container", p.clipToContainer,
          {"", "intersect every surface with the container (grown by a quarter voxel, so that the walls and the "
               "floor hide the water's own faces), so that nothing is drawn outside the tank's walls or below its "
               "floor; false keeps the metaball field's surface as it is (it reaches about R past the outer "
               "particles)"});
}

inline const EnumTable<render::MaterialType> kMaterialType{{"diffuse", render::MaterialType::Diffuse},
                                                          {"dielectric", render::MaterialType::Dielectric},
                                                          {"translucent", render::MaterialType::Translucent},
                                                          {"mirror", render::MaterialType::Mirror}};
inline const EnumTable<render::EnvironmentType> kEnvironmentType{{"gradient", render::EnvironmentType::Gradient},
                                                                {"uniform", render::EnvironmentType::Uniform},
                                                                {"image", render::EnvironmentType::Image}};
inline const EnumTable<ParticleColouring> kParticleColouring{{"kind", ParticleColouring::Kind},
                                                             {"speed", ParticleColouring::Speed},
                                                             {"rest_density_factor", ParticleColouring::RestDensityFactor}};

template <class V>
void describe(V& v, render::Camera& p) {
  v.value("position", p.position, {"m", "eye position"});
  v.value("look_at", p.lookAt, {"m", "point at the image centre"});
  v.value("up", p.up, {"", "up direction (need not be unit length)"});
  v.value("fov", p.verticalFovDegrees, {"deg", "vertical field of view", {0.0, 179.0, true, false}});
  v.value("aperture", p.apertureRadius, {"m", "lens radius for depth of field; 0 = pinhole, all in focus", nonNegative()});
  v.value("focus_distance", p.focusDistance,
          {"m", "distance of the plane in focus along the view direction; 0 = the distance to look_at", nonNegative()});
}

template <class V>
void describe(V& v, render::CameraKey& p) {
  v.value("time", p.time, {"s", "simulated time of this key", nonNegative(), true});
  v.value("position", p.position, {"m", "eye position", anyValue(), true});
  v.value("look_at", p.lookAt, {"m", "point at the image centre", anyValue(), true});
  v.value("fov", p.verticalFovDegrees, {"deg", "vertical field of view", {0.0, 179.0, true, false}});
}

template <class V>
void describe(V& v, render::SunLight& p) {
  v.value("direction", p.direction, {"", "direction the sunlight travels"});
  v.value("irradiance", p.irradiance, {"", "irradiance (RGB) on a surface facing the sun; 0 turns it off", nonNegative()});
  v.value("angular_diameter", p.angularDiameterDegrees,
          {"deg", "apparent size of the sun's disk, for soft shadows; 0 = hard shadows (the real sun: 0.53)",
           {0.0, 90.0, false, true}});
}

template <class V>
void describe(V& v, render::RectLight& p) {
  v.value("corner", p.corner, {"m", "one corner of the rectangle", anyValue(), true});
  v.value("edge_u", p.edgeU, {"m", "first edge from the corner", anyValue(), true});
  v.value("edge_v", p.edgeV, {"m", "second edge; light leaves on the side edge_u x edge_v points to", anyValue(), true});
  v.value("radiance", p.radiance, {"", "emitted radiance (RGB)", nonNegative(), true});
}

template <class V>
void describe(V& v, EnvironmentParams& p) {
  v.enumeration("type", p.type, kEnvironmentType,
                {"", "'gradient' (horizon to zenith colour), 'uniform' (zenith colour everywhere) or 'image' "
                     "(an equirectangular PNG)"});
  v.value("zenith", p.zenith, {"", "sky radiance straight up (RGB); the uniform radiance for 'uniform'", nonNegative()});
  v.value("horizon", p.horizon, {"", "sky radiance at and below the horizon (RGB)", nonNegative()});
  v.value("image", p.image, {"", "equirectangular PNG for 'image', relative to the working directory (e.g. assets/...)"});
  v.value("intensity", p.intensity, {"", "multiplier of the image's linear values", nonNegative()});
  v.value("rotation", p.rotation, {"deg", "rotation of the image about z", between(-360.0, 360.0)});
}

template <class V>
void describe(V& v, render::Material& p) {
  v.enumeration("type", p.type, kMaterialType,
                {"", "'dielectric' (glass, water: Fresnel, refraction, absorption), 'translucent' (tinted soft "
                     "body), 'diffuse' (Lambert) or 'mirror' (smooth conductor)"});
  v.value("albedo", p.albedo, {"", "diffuse albedo, translucent tint or mirror reflectance (RGB)", between(0.0, 1.0)});
  v.value("ior", p.ior, {"", "index of refraction (water 1.33, glass 1.5)", between(1.0, 4.0)});
  v.value("absorption", p.absorption,
          {"1/m", "Beer-Lambert absorption coefficient inside (RGB): light keeps exp(-absorption * distance)",
           nonNegative()});
  v.value("checker_size", p.checkerSize,
          {"m", "3-D checker texture: cells of this size alternate albedo and albedo_b; 0 = plain", nonNegative()});
  v.value("albedo_b", p.albedoB, {"", "second checker colour (RGB)", between(0.0, 1.0)});
}

template <class V>
void describe(V& v, TankParams& p) {
  v.value("enabled", p.enabled, {"", "draw the container's walls that the camera sees from inside (open top)"});
  v.value("height", p.height, {"m", "wall height above container.min; 0 = the container's height", nonNegative()});
  v.object("material", p.material, {"", "wall material (default: a diffuse checker)"});
}

template <class V>
void describe(V& v, FaucetParams& p) {
  v.value("enabled", p.enabled, {"", "draw each emitter as a pipe that comes from above the tank to its nozzle"});
  v.object("material", p.material, {"", "pipe material (default: a grey mirror, brushed metal)"});
}

template <class V>
void describe(V& v, render::ClipPlane& p) {
  v.value("enabled", p.enabled, {"", "cut the surfaces and particles (not the ground) with a plane"});
  v.value("point", p.point, {"m", "a point of the clip plane"});
  v.value("normal", p.normal, {"", "everything on the side this normal points to is removed"});
}

template <class V>
void describe(V& v, ParticleDisplayParams& p) {
  v.value("spheres", p.spheres, {"", "draw the particles as spheres instead of the surfaces"});
  v.value("radius", p.radius, {"m", "sphere radius; 0 = 0.4 fluid spacings", nonNegative()});
  v.enumeration("color_by", p.colourBy, kParticleColouring,
                {"", "sphere colour: 'kind' (fluid blue, bodies other hues), 'speed' or 'rest_density_factor' "
                     "on a colour ramp"});
  v.value("range_min", p.rangeMin, {"", "value at the start of the colour ramp (m/s for speed)"});
  v.value("range_max", p.rangeMax, {"", "value at its end; range_max <= range_min uses the frame's own range"});
}

template <class V>
void describe(V& v, render::Ground& p) {
  v.value("enabled", p.enabled, {"", "draw an infinite ground plane"});
  v.value("point", p.point, {"m", "a point of the ground plane"});
  v.value("normal", p.normal, {"", "ground plane normal"});
  v.value("color_a", p.albedoA, {"", "checker albedo A (RGB)", between(0.0, 1.0)});
  v.value("color_b", p.albedoB, {"", "checker albedo B (RGB)", between(0.0, 1.0)});
  v.value("checker_size", p.checkerSize, {"m", "checker square size; 0 for a plain ground", nonNegative()});
}

template <class V>
void describe(V& v, ChainRadiusParams& p) {
  v.value("root", p.root, {"m", "tube radius at the chain's first particle, where it hangs", positive()});
  v.value("tip", p.tip, {"m", "tube radius at its last particle; linear in between", positive()});
}

inline const EnumTable<render::IntegratorType> kIntegrator{{"path", render::IntegratorType::Path},
                                                       {"whitted", render::IntegratorType::Whitted}};

template <class V>
void describe(V& v, render::EdgeAdaptiveSettings& p) {
  v.value("enabled", p.enabled,
          {"", "first min_samples per pixel, then `samples` where a pixel and one of its four neighbours differ "
               "(edges); off when min_samples >= samples"});
  v.value("threshold", p.threshold,
          {"", "difference (sRGB-encoded, 0..1, any channel) above which a pixel is sampled again", positive()});
  v.value("min_samples", p.minSamples, {"", "sub-pixel samples of every pixel's first pass", between(1, 65536)});
}

template <class V>
void describe(V& v, render::SkyFilterSettings& p) {
  v.value("enabled", p.enabled,
          {"", "interleave the sky directions over tile x tile pixels and average the sky's irradiance over the tile "
               "where neighbours show the same surface (the sun and reflections are not filtered)"});
  v.value("tile", p.tile, {"", "pixels per side of the interleaving tile and the filter's window", between(2, 16)});
  v.value("normal_cosine", p.normalCosine,
          {"", "least cosine between a pixel's and a neighbour's normals for the neighbour to count", between(-0.999, 1.0)});
  v.value("depth_tolerance", p.depthTolerance,
          {"", "largest relative difference of path length to the surface for a neighbour to count", positive()});
}

template <class V>
void describe(V& v, render::WhittedSettings& p) {
  v.value("sky_directions", p.skyDirections,
          {"", "shadow rays towards the sky per diffuse point (fixed cosine-distributed directions)", between(1, 1024)});
  v.value("light_samples", p.lightSamples,
          {"", "points per side of the fixed grid on each area light", between(1, 64)});
  v.value("filter_textures", p.filterTextures,
          {"", "box-filter checker textures over the pixel's footprint (ray cones): far checkers average instead of aliasing"});
  v.value("clamp_secondary", p.clampSecondary,
          {"", "the most a sample's reflected and refracted rays add to it (each channel, linear; 1 = display "
               "white): a sun glint seen by one sample in N lightens its pixel by at most 1/N; 0 = no clamp (exact "
               "HDR). The camera's own view of the sun, sky and lights is never clamped",
           nonNegative()});
  v.object("adaptive", p.adaptive, {"", "edge-adaptive anti-aliasing: more samples only where neighbours differ"});
  v.object("sky_filter", p.skyFilter, {"", "interleaved sky directions, filtered across neighbouring pixels"});
}

template <class V>
void describe(V& v, render::AdaptiveSettings& p) {
  v.value("enabled", p.enabled,
          {"", "path integrator: sample each pixel until its mean is known to relative_error (samples is then ignored)"});
  v.value("relative_error", p.relativeError,
          {"", "target standard error of a pixel's mean luminance, relative to max(mean, 0.05)", positive()});
  v.value("min_samples", p.minSamples, {"", "paths per pixel before the first test, and per batch after it",
                                        between(2, 65536)});
  v.value("max_samples", p.maxSamples, {"", "most paths per pixel", between(2, 65536)});
}

template <class V>
void describe(V& v, render::DenoiseSettings& p) {
  v.value("enabled", p.enabled,
          {"", "path integrator: filter the frame (edge-avoiding a-trous wavelets guided by albedo and normal "
               "buffers, docs/design/rendering.md)"});
  v.value("iterations", p.iterations, {"", "filter passes; the widest reaches 2^(iterations+1) pixels", between(1, 10)});
  v.value("color_sigma", p.colourSigma,
          {"", "relative colour difference at which a neighbour's weight falls to 1/e, at 4 samples per pixel (it "
               "narrows as 1/sqrt(samples), as the noise does)",
           positive()});
  v.value("normal_sigma", p.normalSigma, {"", "normal difference at which a neighbour's weight falls to 1/e", positive()});
  v.value("albedo_sigma", p.albedoSigma, {"", "albedo difference at which a neighbour's weight falls to 1/e", positive()});
}

template <class V>
void describe(V& v, FrameOutputs& p) {
  v.value("png", p.png, {"", "frames/NNNN.png: sRGB, 8 or 16 bits (bit_depth); the video is encoded from these"});
  v.value("exr", p.exr,
          {"", "frames/NNNN.exr: OpenEXR for compositing, linear half-float beauty with alpha and the layers depth.Z, "
               "normal, albedo and object_id (names in the header's kurage:object_names)"});
}

template <class V>
void describe(V& v, RenderParams& p) {
  v.value("width", p.settings.width, {"px", "image width", between(1, 16384)});
  v.value("height", p.settings.height, {"px", "image height", between(1, 16384)});
  v.value("samples", p.settings.samplesPerPixel, {"", "paths per pixel (noise falls as 1/sqrt(samples))", between(1, 65536)});
  v.value("max_depth", p.settings.maxDepth,
          {"", "most scattering events on a path (1 = direct light only); water needs about 8", between(1, 1024)});
  v.value("seed", p.settings.seed, {"", "random seed: another seed gives another noise pattern", between(0, 2147483647)});
  v.value("transmissive_shadows", p.settings.transmissiveShadows,
          {"", "shadow rays pass through water and glass (Fresnel transmission and absorption, without "
               "bending): far less noise under water, no caustics; false = exact light transport"});
  v.enumeration("integrator", p.settings.integrator, kIntegrator,
                {"", "'path' (unbiased path tracing, noise falls with samples) or 'whitted' (deterministic: specular "
                     "reflection and refraction trees, direct light only, noise-free; docs/design/rendering.md)"});
  v.value("environment_sampling", p.settings.environmentSampling,
          {"", "path integrator: sample the sky as a light (by luminance), combined with BSDF sampling by "
               "multiple importance sampling; false = the sky is found only by paths that escape"});
  v.value("fresnel_splitting", p.settings.fresnelSplitting,
          {"", "path integrator: where a camera ray first meets water or glass, trace both the reflected and the "
               "refracted ray instead of choosing one at random (less noise on water surfaces)"});
  v.object("whitted", p.settings.whitted, {"", "settings of the whitted integrator"});
  v.object("adaptive", p.settings.adaptive, {"", "adaptive sampling to a relative error (path integrator)"});
  v.object("denoise", p.settings.denoise, {"", "a denoiser of our own, guided by albedo and normal buffers (path integrator)"});
  v.value("transparent_background", p.settings.transparentBackground,
          {"", "PNG with alpha: the environment is not seen directly, only in reflections and lighting"});
  v.object("outputs", p.outputs, {"", "which files the render stage writes per frame (PNG, OpenEXR or both)"});
  v.value("bit_depth", p.bitDepth, {"", "PNG bits per channel, 8 or 16", between(8, 16)});
  v.object("camera", p.camera, {"", "perspective camera (thin lens when aperture > 0)"});
  v.list("camera_keys", p.cameraKeys,
         {"", "camera keyframes by time, interpolated with a Catmull-Rom spline; when present they replace "
              "camera.position, look_at and fov"});
  v.object("light", p.sun, {"", "the sun: directional light with an angular size (soft shadows)"});
  v.list("area_lights", p.areaLights, {"", "one-sided rectangular area lights"});
  v.object("environment", p.environment, {"", "radiance from directions that hit nothing: sky"});
  v.object("ground", p.ground, {"", "infinite diffuse checker ground plane"});
  v.object("fluid_material", p.fluidMaterial, {"", "material of the fluid surface (default: water)"});
  v.object("body_material", p.bodyMaterial, {"", "material of the bodies' surfaces (default: translucent pink)"});
  v.object("chain_material", p.chainMaterial,
           {"", "material of the tubes drawn along chain bodies (default: translucent orange-pink)"});
  v.object("chain_radius", p.chainRadius,
           {"", "chains are drawn as tubes along a cubic B-spline through their particles (not surfaced), "
                "tapering linearly from root to tip"});
  v.object("tank", p.tank, {"", "the container's walls, drawn"});
  v.object("faucets", p.faucets, {"", "the emitters drawn as pipes (faucets) ending at their nozzles"});
  v.object("clip", p.clip, {"", "clip plane for cross-section views"});
  v.object("particles", p.particles, {"", "particles drawn as spheres, for figures that explain the method"});
}

template <class V>
void describe(V& v, PreviewQuality& p) {
  v.value("width", p.width, {"px", "image width; 0 = half the render width", between(0, 16384)});
  v.value("height", p.height, {"px", "image height; 0 = half the render height", between(0, 16384)});
  v.value("samples", p.samples, {"", "paths per pixel; 0 = a quarter of render.samples, at least 1", between(0, 65536)});
  v.value("max_depth", p.maxDepth, {"", "most scattering events on a path; 0 = render.max_depth, at most 6",
                                    between(0, 1024)});
  v.value("voxel_scale", p.voxelScale, {"", "surface voxel sizes (fluid and bodies) are multiplied by this",
                                        between(1.0, 8.0)});
  v.value("fps", p.fps,
          {"1/s", "frames per second of a preview run (its simulation caches, surfaces and frames are at this rate: "
                  "fewer frames to surface and render); 0 = output.fps", between(0.0, 1000.0)});
}

template <class V>
void describe(V& v, Scene& s) {
  v.ignore("$schema");
  v.value("name", s.name, {"", "scene name, used in file names"});
  v.value("description", s.description, {"", "free text"});
  v.object("fluid", s.sim.fluid, {"", "the SPH fluid (defaults: the paper's parameters, SPEC §2)"});
  v.value("gravity", s.sim.gravity, {"m/s^2", "gravitational acceleration vector (paper: 6.0 downward); z is up"});
  v.object("container", s.sim.container, {"", "the box (tank) with walls on all six sides", {}, true});
  v.list("fluid_blocks", s.sim.fluidBlocks, {"", "boxes filled with fluid particles at t = 0"});
  v.list("emitters", s.sim.emitters, {"", "nozzles that pour fluid in (faucets)"});
  v.list("sinks", s.sim.sinks, {"", "boxes that remove the fluid particles entering them (outflows)"});
  v.list("bodies", s.sim.bodies, {"", "telescopic deformable bodies (springs, stretch-following density, muscles)"});
  v.object("collisions", s.sim.collisions, {"", "collisions between body particles"});
  v.object("time_step", s.sim.timeStep, {"", "time integration step control"});
  v.object("output", s.output, {"", "what to write: duration and frame rate", {}, true});
  v.object("surface", s.surface, {"", "metaball surfacing"});
  v.object("render", s.render, {"", "ray-traced frames"});
  v.object("preview_quality", s.previewQuality,
           {"", "what --quality preview changes: resolution, samples, path depth and surface voxel size"});
}

}  // namespace kurage::pipeline
