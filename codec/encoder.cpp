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
  if (options.level_step < 1) throw std::invalid_argument("encode_stream: level_step < 1");
  std::vector<int> streamed;
  for (size_t i = 0; i < hierarchy.levels.size(); ++i)
    if (i % options.level_step == 0 || i + 1 == hierarchy.levels.size())
      streamed.push_back(static_cast<int>(i));
  if (streamed.empty() || streamed.size() > 0xFFFF)
    throw std::invalid_argument("encode_stream: level count out of range");
  StreamHeader h;
  h.grid = grid;
  h.alpha_policy = alpha_policy;
  h.flags = options.cell_hashes ? kFlagCellHashes : 0;
  h.level_count = static_cast<uint16_t>(streamed.size());
  h.vertex_count = static_cast<uint32_t>(hierarchy.levels[0].vertices.size());

  EncodedStream out;
  out.bytes = write_header(h);
  out.layer_bytes.assign(hierarchy.levels.size(), 0);
  out.streamed_levels = streamed;
  std::vector<uint32_t> coarser;  // V_{l+1}, ascending
  std::vector<MortonCode> known;  // Morton codes of V_{l+1}, ascending
  SetCoderModels models;          // adapted layer after layer, as the decoder's
  models.enable_coordinate_reuse(grid.qbits);
  for (size_t l = streamed.size(); l-- > 0;) {
    const Level& level = hierarchy.levels[streamed[l]];
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
    const auto layer = write_layer(lh, encode_point_set(known, layer_points, grid.qbits, models));
    merge_known(known, layer_points, grid.qbits);
    out.layer_bytes[streamed[l]] = layer.size();
    out.bytes.insert(out.bytes.end(), layer.begin(), layer.end());
    coarser = level.vertices;
  }
  return out;
}

}  // namespace dtm
