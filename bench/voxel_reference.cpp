// voxel_reference: what carving a scan's levels to its voxels gives and
// costs, against carving them to level 0's alpha shape (meshenc
// --no-reference). For each, every level of the stream is decoded and its
// cells are checked against the voxels (the rule of spec/HIERARCHY.md §2.1):
// how many have their centroid outside the solid voxels, and how much of the
// cells' volume lies there; and the stream's bytes.
//
//   voxel_reference VOLUME.nrrd --threshold T [--voxel-interior-step K] [--dmax D]
// prints a markdown table.
#include <cstdio>
#include <string>

#include "codec/decode.h"
#include "codec/encode.h"
#include "core/voxel_solid.h"
#include "mesh/geometry.h"
#include "tools/field_types.h"
#include "tools/formats/input.h"

int main(int argc, char** argv) {
  if (argc < 4 || std::string(argv[2]) != "--threshold") {
    std::fprintf(stderr,
                 "usage: voxel_reference VOLUME.nrrd --threshold T [--voxel-interior-step K] [--dmax D]\n");
    return 2;
  }
  dtm::VolumeOptions volume;
  volume.threshold = std::stod(argv[3]);
  double dmax = 0;
  for (int i = 4; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--voxel-interior-step") volume.interior_step = std::stoi(argv[i + 1]);
    if (a == "--dmax") dmax = std::stod(argv[i + 1]);
  }
  const dtm::InputMesh in = dtm::read_input(argv[1], {}, volume);
  std::printf(
      "| reference | level | vertices | cells | cells with their centroid outside the solid voxels | "
      "their share of the level's volume | stream bytes (all levels, values included) |\n"
      "|---|---:|---:|---:|---:|---:|---:|\n");
  for (const bool voxels : {false, true}) {
    dtm::EncodeInput input;
    input.points = in.points;
    if (in.on_grid) input.lattice = &*in.on_grid;
    std::vector<dtm::EncodeInput::Field> fields;
    for (const auto& f : in.fields)
      fields.push_back({f.name, dtm::value_type(f.type), f.components, f.values});
    input.fields = fields;
    if (voxels) input.voxels = &*in.voxels;
    dtm::EncodeOptions options;
    options.dmax = dmax;
    const dtm::EncodedMesh encoded = dtm::encode(input, options).value();
    const dtm::VoxelSolid solid(*in.voxels, encoded.report.grid, 1.0);
    dtm::ProgressiveDecoder decoder;
    bool first = true;
    const dtm::Status s =
        decoder.feed(encoded.bytes, [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& l) {
          const auto cells = d.carved_cells();
          size_t outside = 0;
          double volume_all = 0, volume_out = 0;
          for (const auto& c : cells) {
            const auto& p = d.points();
            const double v = static_cast<double>(dtm::abs_six_volume(p[c[0]], p[c[1]], p[c[2]], p[c[3]]));
            volume_all += v;
            if (!solid.contains_centroid(p[c[0]], p[c[1]], p[c[2]], p[c[3]])) ++outside, volume_out += v;
          }
          std::printf("| %s | %d | %u | %zu | %zu (%.2f%%) | %.2f%% | %s |\n",
                      voxels ? "the voxels" : "level 0's alpha carving", l.level, l.vertices, cells.size(),
                      outside, 100.0 * outside / std::max<size_t>(1, cells.size()),
                      100.0 * volume_out / std::max(1.0, volume_all),
                      first ? std::to_string(encoded.bytes.size()).c_str() : "");
          first = false;
        });
    if (!s.ok()) return 1;
  }
  return 0;
}
