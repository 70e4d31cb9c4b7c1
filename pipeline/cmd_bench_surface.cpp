// kurage bench surface (not written yet)
#include "pipeline/cli.h"

namespace kurage::pipeline {

int benchSurface(ArgParser& args) {
  args.fail("not implemented yet");
}

}  // namespace kurage::pipeline
