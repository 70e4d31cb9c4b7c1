// Internal to render/: the definition of LevelSet::Impl, for the few .cpp files that build
// level sets with OpenVDB. Not for callers outside render/ (they use render/surfacing.h).
#pragma once

#include "render/surfacing.h"

#include <openvdb/openvdb.h>

namespace kurage::render {

struct LevelSet::Impl {
  openvdb::FloatGrid::Ptr grid;  // null for a default-constructed level set
};

}  // namespace kurage::render
