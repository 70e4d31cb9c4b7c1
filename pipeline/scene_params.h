// The parameter registry: for every component of a scene, its JSON keys, units, documentation
// and valid ranges, next to the struct it fills. Defaults are the structs' own initial values
// (sim/params.h holds the paper's, SPEC §2). Used only through the visitors of
// pipeline/param_visitor.h; include it in .cpp files only.
#pragma once

#include "pipeline/param_visitor.h"
#include "pipeline/scene.h"

namespace kurage::pipeline {

inline const EnumTable<sim::NegativePressure> kNegativePressure{{"clamp", sim::NegativePressure::Clamp},
                                                                {"keep", sim::NegativePressure::Keep}};
inline const EnumTable<sim::WallSlip> kWallSlip{{"no_slip", sim::WallSlip::NoSlip},
                                                {"free_slip", sim::WallSlip::FreeSlip}};
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
}

template <class V>
void describe(V& v, sim::ContainerParams& p) {
  v.value("min", p.min, {"m", "lower corner of the box that holds everything", anyValue(), true});
  v.value("max", p.max, {"m", "upper corner of the box", anyValue(), true});
  v.enumeration("walls", p.walls, kWallSlip,
                {"", "'no_slip' (the paper): a particle that enters a wall is put back on it and stopped; "
                     "'free_slip': put back, only the velocity into the wall removed"});
}

template <class V>
void describe(V& v, sim::FluidBlock& p) {
  v.value("min", p.min, {"m", "lower corner; particles start half a spacing inside", anyValue(), true});
  v.value("max", p.max, {"m", "upper corner", anyValue(), true});
}

template <class V>
void describe(V& v, sim::TimeStepParams& p) {
  v.enumeration("mode", p.mode, kTimeStepMode, {"", "'adaptive' (bounded by CFL, viscosity, force) or 'fixed'"});
  v.value("fixed_step", p.fixedStep, {"s", "the step when mode is 'fixed'", positive()});
  v.value("cfl", p.cflFactor, {"", "CFL factor: dt <= cfl h / (c + |v|max)", {0.0, 1.0, true, false}});
  v.value("viscous_factor", p.viscousFactor, {"", "dt <= factor h^2 / nu", {0.0, 1.0, true, false}});
  v.value("force_factor", p.forceFactor, {"", "dt <= factor sqrt(h / |a|max)", {0.0, 1.0, true, false}});
  v.value("max_step", p.maxStep, {"s", "largest adaptive step", positive()});
  v.value("min_step", p.minStep, {"s", "floor of the adaptive step: a bound below it stops the run", positive()});
}

template <class V>
void describe(V& v, OutputParams& p) {
  v.value("duration", p.duration, {"s", "simulated time; frames from t = 0 to t = duration", positive(), true});
  v.value("fps", p.fps, {"1/s", "output frames per second of simulated time", {0.0, 1000.0, true, false}});
}

template <class V>
void describe(V& v, render::MetaballParams& p) {
  v.value("radius", p.radius, {"m", "field radius R of each particle's blob s (1 - (r/R)^2)^2", positive()});
  v.value("threshold", p.threshold, {"", "the surface is where the summed field equals this", positive()});
  v.value("strength", p.strength, {"", "blob strength s (POV-Ray's component strength)", positive()});
  v.value("voxel_size", p.voxelSize, {"m", "level set voxel size", positive()});
  v.value("half_width", p.halfWidth, {"voxels", "narrow band half width", between(2.0, 10.0)});
}

template <class V>
void describe(V& v, SurfaceParams& p) {
  v.object("fluid", p.fluid, {"", "metaball surface of the fluid particles"});
}

template <class V>
void describe(V& v, render::Camera& p) {
  v.value("position", p.position, {"m", "eye position"});
  v.value("look_at", p.lookAt, {"m", "point at the image centre"});
  v.value("up", p.up, {"", "up direction (need not be unit length)"});
  v.value("fov", p.verticalFovDegrees, {"deg", "vertical field of view", {0.0, 179.0, true, false}});
}

template <class V>
void describe(V& v, render::DirectionalLight& p) {
  v.value("direction", p.direction, {"", "direction the light travels"});
  v.value("radiance", p.radiance, {"", "irradiance (RGB) on a surface facing the light", nonNegative()});
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
void describe(V& v, MaterialParams& p) {
  v.value("albedo", p.albedo, {"", "Lambert albedo (RGB)", between(0.0, 1.0)});
}

template <class V>
void describe(V& v, RenderParams& p) {
  v.value("width", p.settings.width, {"px", "image width", between(1, 16384)});
  v.value("height", p.settings.height, {"px", "image height", between(1, 16384)});
  v.value("samples", p.settings.samplesPerPixel, {"", "samples per pixel (anti-aliasing)", between(1, 4096)});
  v.value("sky_zenith", p.settings.skyZenith, {"", "sky colour overhead (RGB radiance)", nonNegative()});
  v.value("sky_horizon", p.settings.skyHorizon, {"", "sky colour at the horizon (RGB radiance)", nonNegative()});
  v.value("ambient", p.settings.ambient, {"", "fraction of the sky colour added as ambient light", between(0.0, 1.0)});
  v.object("camera", p.camera, {"", "pinhole camera"});
  v.object("light", p.light, {"", "directional light with shadows"});
  v.object("ground", p.ground, {"", "ground plane"});
  v.object("fluid_material", p.fluidMaterial, {"", "material of the fluid surface"});
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
  v.object("time_step", s.sim.timeStep, {"", "time integration step control"});
  v.object("output", s.output, {"", "what to write: duration and frame rate", {}, true});
  v.object("surface", s.surface, {"", "metaball surfacing"});
  v.object("render", s.render, {"", "ray-traced frames"});
}

}  // namespace kurage::pipeline
