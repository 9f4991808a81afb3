// Every input reader on arbitrary bytes: a FormatError naming the problem,
// or points that can make a tetrahedral mesh (finite, at least 4, not all
// coplanar), every cell and tagged face on them, a second-order mesh's
// edge nodes set aside, a label for each cell and face that has labels,
// never a crash. The first byte's low 4 bits pick the format,
// its high 4 bits the voxel threshold and interior step; the rest is the file.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_check.h"
#include "tools/formats/input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".node", ".mesh", ".vtk", ".vtu", ".msh", ".nrrd", ".ply",
                                      ".off",  ".obj",  ".xyz", ".vol", ".inp", ".e"};
  const char* ext = kExtensions[(data[0] & 15) % 13];
  const std::string path = "/tmp/dtm_fuzz_input_" + std::to_string(getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  dtm::VolumeOptions volume;
  volume.threshold = static_cast<double>(data[0] >> 4);
  volume.interior_step = 1 + (data[0] >> 6);
  try {
    // No .ele is read: a stray one beside the temporary file must not matter.
    const dtm::InputMesh in = dtm::read_input(path, {}, volume, false);
    FUZZ_CHECK(in.points.size() >= 4);
    for (const auto& p : in.points)
      FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    for (const auto& t : in.tets)
      for (auto v : t) FUZZ_CHECK(v < in.points.size());
    for (const auto& f : in.tagged_faces)
      for (auto v : f) FUZZ_CHECK(v < in.points.size());
    // Labels, one a cell (a split cell's on each of its tetrahedra).
    FUZZ_CHECK(in.tet_regions.empty() || in.tet_regions.size() == in.tets.size());
    FUZZ_CHECK(in.face_tags.empty() || in.face_tags.size() == in.tagged_faces.size());
    // A second-order mesh's edge nodes: set aside, each indexing them.
    FUZZ_CHECK(in.tet_edge_nodes.empty() || in.tet_edge_nodes.size() == in.tets.size());
    for (const auto& e : in.tet_edge_nodes)
      for (auto v : e) FUZZ_CHECK(v == dtm::InputMesh::kNoEdgeNode || v < in.edge_points.size());
    FUZZ_CHECK(in.other_edge_nodes.empty());
    for (const auto& field : in.fields)
      FUZZ_CHECK(field.values.size() == static_cast<size_t>(field.components) * in.points.size());
    for (const auto& field : in.cell_fields)
      FUZZ_CHECK(field.values.size() == static_cast<size_t>(field.components) * in.tets.size());
  } catch (const dtm::FormatError&) {
  }
  std::remove(path.c_str());
  return 0;
}
