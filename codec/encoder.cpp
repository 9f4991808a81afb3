#include "encoder.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "bitstream/point_set_coder.h"
#include "codec/format.h"

namespace dtm {

EncodedStream encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                            const Grid& grid, AlphaPolicy::Kind alpha_policy,
                            const EncoderOptions& options) {
  const auto& levels = hierarchy.levels;
  if (levels.empty() || levels.size() > 0xFFFF)
    throw std::invalid_argument("encode_stream: level count out of range");
  StreamHeader h;
  h.grid = grid;
  h.alpha_policy = alpha_policy;
  h.flags = options.cell_hashes ? kFlagCellHashes : 0;
  h.level_count = static_cast<uint16_t>(levels.size());
  h.vertex_count = static_cast<uint32_t>(levels[0].vertices.size());

  EncodedStream out;
  out.bytes = write_header(h);
  out.layer_bytes.assign(levels.size(), 0);
  std::vector<uint32_t> coarser;  // V_{l+1}, ascending
  for (size_t l = levels.size(); l-- > 0;) {
    const Level& level = levels[l];
    std::vector<uint32_t> added;
    std::set_difference(level.vertices.begin(), level.vertices.end(), coarser.begin(),
                        coarser.end(), std::back_inserter(added));
    if (added.size() + coarser.size() != level.vertices.size())
      throw std::invalid_argument("encode_stream: levels are not nested");
    std::vector<GridPoint> layer_points;
    layer_points.reserve(added.size());
    for (uint32_t i : added) layer_points.push_back(points[i]);

    LayerHeader lh;
    lh.level = static_cast<uint16_t>(l);
    lh.new_vertices = static_cast<uint32_t>(added.size());
    lh.level_vertices = static_cast<uint32_t>(level.vertices.size());
    lh.alpha = level.alpha;
    if (options.cell_hashes) lh.cell_hash = cell_set_hash(points, level.mesh);
    const auto layer = write_layer(lh, encode_point_set(layer_points, grid.qbits));
    out.layer_bytes[l] = layer.size();
    out.bytes.insert(out.bytes.end(), layer.begin(), layer.end());
    coarser = level.vertices;
  }
  return out;
}

}  // namespace dtm
