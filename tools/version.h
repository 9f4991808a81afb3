// What every tool prints for --version: the project's version (CMake's
// project(VERSION)) and the stream versions it writes and reads.
#pragma once

#include <string>

#include "codec/format.h"

namespace dtm {

inline std::string version_text(const char* tool) {
  return std::string(tool) + " (dtmesh " DTM_VERSION "): writes .dtm " + std::to_string(kVersionMajor) + "." +
         std::to_string(kVersionMinor) + ", reads .dtm " + std::to_string(kOldestVersionMajor) + ".x to " +
         std::to_string(kVersionMajor) + ".x";
}

}  // namespace dtm
