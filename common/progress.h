// Long work says what it is doing: the encoder names each phase as it
// starts (tools show it on a terminal, or time it with --verbose). A phase's
// name is a short sentence fragment, "level 2: checking the shape".
#pragma once

#include <functional>
#include <string_view>

namespace dtm {

using PhaseCallback = std::function<void(std::string_view phase)>;

// Calls `on_phase` if there is one.
inline void report_phase(const PhaseCallback& on_phase, std::string_view phase) {
  if (on_phase) on_phase(phase);
}

}  // namespace dtm
