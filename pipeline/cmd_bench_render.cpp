// kurage bench render (not written yet)
#include "pipeline/cli.h"

namespace kurage::pipeline {

int benchRender(ArgParser& args) {
  args.fail("not implemented yet");
}

}  // namespace kurage::pipeline
