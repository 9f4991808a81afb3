// What the bench tools read from the environment (their knobs: BOXES=12 ...).
#pragma once

#include <cstdlib>

namespace dtm::bench {

// The number in environment variable `name`, or `fallback` when it is unset.
inline double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

}  // namespace dtm::bench
