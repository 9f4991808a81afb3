// Exodus II in a build without libexodusii (tools/CMakeLists.txt): the
// tools say how to get it.
#include <stdexcept>

#include "exodus.h"
#include "format_error.h"

namespace dtm {

namespace {
constexpr const char* kHow =
    "this build has no Exodus II (apt-get install libexodusii-dev, then rebuild; or read it through the "
    "Python package: python3 -c \"import dtmesh, meshio; meshio.write('out.dtm', meshio.read('in.e'))\", "
    "which keeps its tetrahedra and variables, not its blocks and side sets)";
}

InputMesh read_exodus(const std::string& path, int) { throw FormatError(path + ": " + kHow); }

std::string render_exodus(const OutputMesh&) { throw std::invalid_argument(kHow); }

std::vector<std::string> exodus_renumbering(const OutputMesh&) { return {}; }

}  // namespace dtm
