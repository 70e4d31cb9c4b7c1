#include "sim/time_step.h"

#include <cmath>
#include <limits>

namespace kurage::sim {

std::string_view stepBoundName(StepBound bound) {
  switch (bound) {
    case StepBound::Fixed: return "fixed";
    case StepBound::Cfl: return "cfl";
    case StepBound::Viscous: return "viscous";
    case StepBound::Force: return "force";
    case StepBound::Spring: return "spring";
    case StepBound::Pressure: return "pressure";
    case StepBound::Maximum: return "maximum";
    case StepBound::Count: break;
  }
  return "?";
}

StepLimit adaptiveStep(const TimeStepParams& params, const StepInputs& in) {
  StepLimit limit{params.maxStep, StepBound::Maximum};
  auto consider = [&limit](float step, StepBound bound) {
    if (std::isfinite(step) && step < limit.step) limit = {step, bound};
  };
  const float cflLength = in.cflLength > 0.0f ? in.cflLength : in.supportRadius;
  consider(params.cflFactor * cflLength / (in.speedOfSound + in.maxSpeed), StepBound::Cfl);
  if (in.kinematicViscosity > 0.0f)
    consider(params.viscousFactor * in.supportRadius * in.supportRadius / in.kinematicViscosity, StepBound::Viscous);
  if (in.maxAcceleration > 0.0f)
    consider(params.forceFactor * std::sqrt(in.supportRadius / in.maxAcceleration), StepBound::Force);
  if (in.springStep > 0.0f) consider(params.springFactor * in.springStep, StepBound::Spring);
  if (in.pressureStep > 0.0f) consider(params.pressureFactor * in.pressureStep, StepBound::Pressure);
  return limit;
}

StepLimit stabilityBound(const TimeStepParams& params, const StepInputs& inputs) {
  TimeStepParams unlimited = params;
  unlimited.maxStep = std::numeric_limits<float>::infinity();
  return adaptiveStep(unlimited, inputs);
}

}  // namespace kurage::sim
