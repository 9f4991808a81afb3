#include "web/level_view.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <utility>

#include "common/checksum.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

template <class T>
uint64_t hash_of(std::span<const T> items) {
  return xxh3_64(std::span(reinterpret_cast<const uint8_t*>(items.data()), items.size_bytes()));
}

std::string hex(uint64_t h) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016" PRIx64, h);
  return buffer;
}

// JSON string contents: field names are the stream's bytes, anything at all.
std::string json_escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[7];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::array<double, 3> grid_centre(const Grid& grid) {
  const double half = static_cast<double>(uint64_t{1} << (grid.qbits - 1)) * grid.step;
  return {grid.origin[0] + half, grid.origin[1] + half, grid.origin[2] + half};
}

LevelViewer::LevelViewer(DecoderOptions options) : decoder_(std::move(options)) {}

Status LevelViewer::feed(std::span<const uint8_t> bytes) {
  if (!error_.ok()) return error_;
  const Status s =
      decoder_.feed(bytes, [this](const ProgressiveDecoder& d, const DecodedLevel& l) { make_view(d, l); });
  // A level whose mesh cannot be made (a damaged carving section, a
  // degenerate point set) ends the stream as a damaged layer does.
  if (s.ok() && !decoder_.mesh_status().ok()) error_ = decoder_.mesh_status();
  if (!s.ok()) error_ = s;
  return error_;
}

Status LevelViewer::finish() const { return error_.ok() ? decoder_.finish() : error_; }

LevelView LevelViewer::take_level() {
  LevelView view = std::move(ready_.front());
  ready_.pop_front();
  return view;
}

void LevelViewer::make_view(const ProgressiveDecoder& d, const DecodedLevel& level) {
  if (!d.mesh_status().ok()) return;  // an earlier level's mesh failed: feed() reports it
  // DT's cells, and at level 0 of an exact stream the input's other cells.
  const ProgressiveDecoder::LevelCells cells = d.level_cells();
  if (!d.mesh_status().ok()) return;
  const TetMesh& dt = cells.mesh;
  const std::vector<uint8_t>& kept = cells.kept;

  LevelView v;
  v.level = level.level;
  v.vertices = level.vertices;
  // d.levels() ends with this level; the one before it is the next coarser.
  const size_t n = d.levels().size();
  v.first_new = n >= 2 ? d.levels()[n - 2].vertices : 0;
  v.stream_bytes = level.stream_bytes;

  std::vector<int32_t> index(dt.cells.size(), -1);
  for (size_t c = 0; c < dt.cells.size(); ++c)
    if (kept[c]) {
      index[c] = static_cast<int32_t>(v.cells.size());
      v.cells.push_back(dt.cells[c]);
      v.cell_regions.push_back(kept[c]);
    }
  v.cell_neighbors.reserve(v.cells.size());
  for (size_t c = 0; c < dt.cells.size(); ++c) {
    if (!kept[c]) continue;
    std::array<int32_t, 4> n;
    for (int i = 0; i < 4; ++i) n[i] = dt.neighbors[c][i] < 0 ? -1 : index[dt.neighbors[c][i]];
    v.cell_neighbors.push_back(n);
  }
  const std::span<const GridPoint> points(d.points().data(), level.vertices);
  for (const BoundaryFace& f : boundary_faces(dt, kept)) {
    v.surface.push_back(outward_triangle(dt, points, f));
    v.surface_regions.push_back(kept[f.cell]);
  }
  v.boundary = boundary_vertices(dt, level.vertices, kept);

  const Grid& grid = d.header().grid;
  const std::array<double, 3> centre = grid_centre(grid);
  v.new_positions.reserve(3 * size_t{level.vertices - v.first_new});
  for (uint32_t i = v.first_new; i < level.vertices; ++i) {
    const InputPoint p = grid.to_input(points[i]);
    v.new_positions.push_back(static_cast<float>(p.x - centre[0]));
    v.new_positions.push_back(static_cast<float>(p.y - centre[1]));
    v.new_positions.push_back(static_cast<float>(p.z - centre[2]));
  }
  for (const FieldValues& f : d.fields()) {
    const int components = f.description.components;
    std::vector<float> values;
    values.reserve(size_t{level.vertices - v.first_new} * components);
    for (uint32_t i = v.first_new; i < level.vertices; ++i)
      for (int k = 0; k < components; ++k) values.push_back(static_cast<float>(f.value(i, k)));
    v.new_values.push_back(std::move(values));
  }
  ready_.push_back(std::move(v));
}

std::string level_summary_json(const ProgressiveDecoder& decoder, const LevelView& view) {
  const std::span<const GridPoint> points(decoder.points().data(), view.vertices);
  // The surface as a set: each face turned to start at its least corner,
  // then sorted (the decoder's threads order the faces differently from run
  // to run), its region beside it where the stream has regions.
  const bool regions = !decoder.regions().empty();
  std::vector<std::array<uint32_t, 4>> surface;
  for (size_t i = 0; i < view.surface.size(); ++i) {
    std::array<uint32_t, 3> t = view.surface[i];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    surface.push_back({t[0], t[1], t[2], regions ? view.surface_regions[i] : 0u});
  }
  std::sort(surface.begin(), surface.end());
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<uint32_t> face_regions;
  for (const auto& f : surface) {
    faces.push_back({f[0], f[1], f[2]});
    face_regions.push_back(f[3]);
  }
  std::string json =
      "{\"level\": " + std::to_string(view.level) + ", \"vertices\": " + std::to_string(view.vertices) +
      ", \"tetrahedra\": " + std::to_string(view.cells.size()) +
      ", \"surface_triangles\": " + std::to_string(view.surface.size()) + ", \"boundary_vertices\": " +
      std::to_string(std::count(view.boundary.begin(), view.boundary.end(), 1)) +
      ", \"stream_bytes\": " + std::to_string(view.stream_bytes) + ", \"points_hash\": \"" +
      hex(hash_of(points)) + "\"" + ", \"cell_hash\": \"" + hex(cell_set_hash(points, view.cells)) + "\"" +
      ", \"surface_hash\": \"" + hex(hash_of(std::span<const std::array<uint32_t, 3>>(faces))) + "\"" +
      ", \"boundary_hash\": \"" + hex(hash_of(std::span<const uint8_t>(view.boundary))) + "\"" +
      ", \"fields\": [";
  for (size_t f = 0; f < decoder.fields().size(); ++f) {
    const FieldValues& field = decoder.fields()[f];
    const std::span<const uint64_t> bits(field.bits.data(),
                                         size_t{view.vertices} * field.description.components);
    json += (f ? ", " : "") + std::string("{\"name\": \"") + json_escaped(field.description.name) +
            "\", \"values_hash\": \"" + hex(hash_of(bits)) + "\"}";
  }
  json += "]";
  if (regions) {
    json += ", \"surface_regions_hash\": \"" + hex(hash_of(std::span<const uint32_t>(face_regions))) +
            "\", \"regions\": [";
    for (size_t r = 0; r < decoder.regions().size(); ++r) {
      std::vector<std::array<uint32_t, 4>> cells;
      for (size_t c = 0; c < view.cells.size(); ++c)
        if (view.cell_regions[c] == r + 1) cells.push_back(view.cells[c]);
      const RegionLabel& region = decoder.regions()[r];
      json += (r ? ", " : "") + std::string("{\"label\": ") + std::to_string(region.label) +
              ", \"name\": \"" + json_escaped(region.name) +
              "\", \"tetrahedra\": " + std::to_string(cells.size()) + ", \"cell_hash\": \"" +
              hex(cell_set_hash(points, cells)) + "\"}";
    }
    json += "]";
  }
  return json + "}";
}

std::string end_summary_json(const Status& end) {
  const char* how = end.ok() ? "done" : end.code() == StatusCode::kTruncated ? "truncated" : "error";
  return std::string("{\"end\": \"") + how + "\", \"message\": \"" + json_escaped(end.message()) + "\"}";
}

}  // namespace dtm
