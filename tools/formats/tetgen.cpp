#include "tetgen.h"

#include <cmath>
#include <filesystem>
#include <string_view>

#include "text_records.h"

namespace dtm {

namespace {

// The header of a .node: read by next(), checked.
struct NodeHeader {
  uint64_t count = 0;
  int attributes = 0;
  int has_marker = 0;
};
NodeHeader node_header(TextRecords& r, const std::string& path) {
  TextRecords::Fields tok;
  if (!r.next(tok)) throw FormatError(path + ": empty file, expected a .node header");
  const size_t header = r.line();
  if (tok.size() < 2 || tok.size() > 4)
    r.fail(header, "expected a header '<points> <dimension> [<attributes> <markers>]'");
  NodeHeader h;
  h.count = r.parse<uint64_t>(tok[0], "a point count", header);
  const auto dim = r.parse<int>(tok[1], "a dimension", header);
  h.attributes = tok.size() > 2 ? r.parse<int>(tok[2], "an attribute count", header) : 0;
  h.has_marker = tok.size() > 3 ? r.parse<int>(tok[3], "0 or 1 boundary markers", header) : 0;
  if (dim != 3) r.fail(header, "dimension must be 3, got " + std::to_string(dim));
  if (h.attributes < 0 || h.has_marker < 0 || h.has_marker > 1)
    r.fail(header, "bad attribute or marker count");
  if (h.count > (uint64_t{1} << 31))
    r.fail(header, "point count " + std::to_string(h.count) + " is too large");
  return h;
}

// read_tetgen_node() of part `part` of `parts` of the records (all of them
// when parts is 1): in a part, each record's index follows its first's.
NodePart read_node(const std::string& path, int part, int parts) {
  TextRecords r(path);
  TextRecords::Fields tok;
  const NodeHeader h = node_header(r, path);
  r.keep_to_part(part, parts);
  const uint64_t count = h.count;
  const int attributes = h.attributes, has_marker = h.has_marker;

  NodePart result;
  NodeFile& out = result.node;
  const auto per_point = static_cast<size_t>(attributes);
  const size_t expected = 4 + per_point + static_cast<size_t>(has_marker);
  int64_t first_index = 0;
  // Room for n more points: the vectors grow by what the file holds (room()),
  // never by what its header claims.
  const auto grow = [&](size_t n) {
    out.points.resize(out.points.size() + n);
    out.attributes.resize(out.points.size() * per_point);
    if (has_marker) out.markers.resize(out.points.size());
  };
  const auto point = [&](size_t at, size_t line, const TextRecords::Fields& f) {
    if (f.size() != expected)
      r.fail(line, "expected " + std::to_string(expected) + " fields, found " + std::to_string(f.size()));
    if (at >= out.points.size()) return;  // past the block's room: an earlier line is wrong
    const auto index = r.parse<int64_t>(f[0], "a point index", line);
    if (at > 0 && index != first_index + static_cast<int64_t>(at))
      r.fail(line, "point index " + std::to_string(index) + " out of sequence");
    const InputPoint p{r.parse<double>(f[1], "a coordinate", line),
                       r.parse<double>(f[2], "a coordinate", line),
                       r.parse<double>(f[3], "a coordinate", line)};
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      r.fail(line, "coordinate is not finite");
    out.points[at] = p;
    for (size_t a = 0; a < per_point; ++a)
      out.attributes[at * per_point + a] = r.parse<double>(f[4 + a], "an attribute", line);
    if (has_marker) out.markers[at] = r.parse<int>(f[expected - 1], "a boundary marker", line);
  };
  // The first point on its own (its index, 0 or 1, numbers the rest), the
  // others a block at a time on every core.
  uint64_t read = 0;
  size_t extra = 0;  // the line of a record past `count`
  const auto none = [](size_t, size_t, const TextRecords::Fields&) {};
  if (count == 0) {
    extra = r.records(
                 0, [](size_t, size_t) {}, none, [] {})
                .extra_line;
  } else if (r.next(tok)) {
    if (tok.size() != expected)
      r.fail(r.line(),
             "expected " + std::to_string(expected) + " fields, found " + std::to_string(tok.size()));
    first_index = r.parse<int64_t>(tok[0], "a point index", r.line());
    // (A part's first record may be any point: joining the parts checks it.)
    if (parts == 1 && first_index != 0 && first_index != 1)
      r.fail(r.line(), "the first point index must be 0 or 1");
    grow(1);
    point(0, r.line(), tok);
    size_t first = 0;
    const TextRecords::Found rest = r.records(
        count - 1,
        [&](size_t n, size_t bytes) {
          first = out.points.size(), grow(TextRecords::room(n, bytes, expected));
        },
        [&](size_t i, size_t line, const TextRecords::Fields& f) { point(first + i, line, f); }, [] {});
    read = 1 + rest.records;
    extra = rest.extra_line;
  }
  if (read < count && parts == 1)
    throw FormatError(path + ": file ends after " + std::to_string(read) + " of " + std::to_string(count) +
                      " points");
  if (extra) r.fail(extra, "unexpected data after the " + std::to_string(count) + " points");
  out.points.resize(read);  // a part's room may exceed what it holds
  out.attributes.resize(read * per_point);
  if (has_marker) out.markers.resize(read);
  out.index_base = parts == 1 && read > 0 ? static_cast<int>(first_index) : 0;
  out.attribute_count = attributes;
  result.header_count = count;
  result.has_markers = has_marker != 0;
  result.first_index = read > 0 ? first_index : -1;
  return result;
}

}  // namespace

NodeFile read_tetgen_node(const std::string& path) { return read_node(path, 0, 1).node; }

NodePart read_tetgen_node_part(const std::string& path, int part, int parts) {
  return read_node(path, part, parts);
}

void fail_at_node_record(const std::string& path, int part, int parts, uint64_t record,
                         const std::string& problem) {
  TextRecords r(path);
  node_header(r, path);
  r.keep_to_part(part, parts);
  TextRecords::Fields tok;
  for (uint64_t i = 0; i <= record; ++i)
    if (!r.next(tok)) throw FormatError(path + ": " + problem);  // not reached: the part holds the record
  r.fail(r.line(), problem);
}

int tetgen_ele_attributes(const std::string& path) {
  TextRecords r(path, 4096);  // the header only: not a whole block of records
  TextRecords::Fields tok;
  if (!r.next(tok) || tok.size() < 3) return 0;
  return std::max(0, r.parse<int>(tok[2], "an attribute count", r.line()));
}

namespace {

using Tet = std::array<uint32_t, 4>;

// read_tetgen_ele() of part `part` of `parts` of the records (all of them
// when parts is 1), the counts in `counts`.
// TetGen -o2's 10-node tetrahedron numbers its edge nodes 4 (2,3), 5 (0,3),
// 6 (0,1), 7 (1,2), 8 (1,3), 9 (0,2): theirs in kTetEdges' order
// (second_order.h).
constexpr std::array<size_t, 6> kTetgenTetEdgeNodes = {6, 9, 5, 7, 8, 4};

std::vector<std::array<uint32_t, 4>> read_ele(const std::string& path, size_t num_points, int index_base,
                                              const std::function<bool(const std::array<uint32_t, 4>&)>& keep,
                                              std::vector<int32_t>* regions, int part, int parts,
                                              ElePart& counts, const EleBlock& take = {},
                                              std::vector<std::array<uint32_t, 6>>* edge_nodes = nullptr,
                                              std::vector<double>* first_attribute = nullptr) {
  TextRecords r(path);
  TextRecords::Fields tok;
  if (!r.next(tok)) throw FormatError(path + ": empty file, expected an .ele header");
  const size_t header = r.line();
  if (tok.size() < 2 || tok.size() > 3)
    r.fail(header, "expected a header '<tetrahedra> <nodes per tet> [<attributes>]'");
  const auto count = r.parse<uint64_t>(tok[0], "a tetrahedron count", header);
  const auto per = r.parse<int>(tok[1], "nodes per tetrahedron", header);
  const int attributes = tok.size() > 2 ? r.parse<int>(tok[2], "an attribute count", header) : 0;
  if (per != 4 && per != 10)
    r.fail(header, "tetrahedra of 4 or 10 nodes (TetGen -o2) are read, not of " + std::to_string(per));
  // (A second-order .ele is read whole: its edge nodes go with its tetrahedra.)
  if (per == 10 && (!edge_nodes || keep || parts != 1))
    r.fail(header,
           "a second-order .ele (10 nodes per tetrahedron, TetGen -o2) is read whole, on one process "
           "(not under mpirun)");
  if (attributes < 0) r.fail(header, "bad attribute count");
  r.keep_to_part(part, parts);
  std::vector<Tet> out;
  // Room for all at once (growing by doubling held 1.5x the tetrahedra
  // while copying, and up to twice as many): no more than the file's bytes
  // allow, 10 to a line at least, whatever its header claims. Those kept of
  // a share, an unknown count, are held in pieces and copied once into room
  // for exactly them, each piece freed when copied (one vector grown, then
  // shrunk, held up to twice them: bunny_10m's share on one of 2 ranks
  // peaked at 1.3 GB).
  std::error_code size_error;
  const uint64_t bytes = std::filesystem::file_size(path, size_error);
  if (!keep) out.reserve(std::min<uint64_t>(count, size_error ? uint64_t{1} << 20 : bytes / 10));
  // (With `take`, the block's regions go with its tetrahedra.)
  const bool with_regions = regions && attributes > 0 && (!keep || take) && !first_attribute;
  // (Or, with `first_attribute` and no `keep`, the first attribute as it is.)
  const bool with_attribute = first_attribute && attributes > 0 && !keep;
  std::vector<Tet> block;                     // with `keep`: the block's tetrahedra, before the choice
  std::vector<int32_t> block_regions;         // with `take`: theirs
  constexpr size_t kPiece = size_t{1} << 17;  // tetrahedra: 2 MiB
  std::vector<std::vector<Tet>> pieces;
  const size_t fields = 1 + static_cast<size_t>(per) + static_cast<size_t>(attributes);
  size_t room = 0;    // the block's tetrahedra that can be whole
  Tet* at = nullptr;  // where the block's tetrahedra go
  int32_t* region_at = nullptr;
  double* attribute_at = nullptr;
  std::array<uint32_t, 6>* edge_at = nullptr;  // and their edge nodes (10 nodes per tetrahedron)
  const TextRecords::Found found = r.records(
      count,
      [&](size_t n, size_t bytes) {
        n = TextRecords::room(n, bytes, fields);
        room = n;
        if (keep) {
          block.resize(n);
          at = block.data();
          if (with_regions) block_regions.resize(n), region_at = block_regions.data();
          return;
        }
        out.resize(out.size() + n);
        at = out.data() + (out.size() - n);
        if (per == 10) {
          edge_nodes->resize(edge_nodes->size() + n);
          edge_at = edge_nodes->data() + (edge_nodes->size() - n);
        }
        if (with_regions) {
          regions->resize(regions->size() + n);
          region_at = regions->data() + (regions->size() - n);
        }
        if (with_attribute) {
          first_attribute->resize(first_attribute->size() + n);
          attribute_at = first_attribute->data() + (first_attribute->size() - n);
        }
      },
      [&](size_t i, size_t line, const TextRecords::Fields& f) {
        if (f.size() != fields) r.fail(line, "expected " + std::to_string(fields) + " fields");
        if (i >= room) return;  // past the block's room: an earlier line is wrong
        const auto node = [&](size_t k) {
          const auto v = r.parse<int64_t>(f[1 + k], "a vertex index", line) - index_base;
          if (v < 0 || static_cast<uint64_t>(v) >= num_points)
            r.fail(line, "vertex index " + std::string(f[1 + k]) + " out of range");
          return static_cast<uint32_t>(v);
        };
        Tet t;
        for (size_t k = 0; k < 4; ++k) t[k] = node(k);
        if (per == 10)
          for (size_t k = 0; k < 6; ++k) edge_at[i][k] = node(kTetgenTetEdgeNodes[k]);
        if (with_regions) {
          const std::string_view first = f[1 + static_cast<size_t>(per)];
          const auto a = r.parse<double>(first, "a region attribute", line);
          if (a != std::floor(a) || a < INT32_MIN || a > INT32_MAX)
            r.fail(line, "a region attribute that is not a 32-bit integer: " + std::string(first));
          region_at[i] = static_cast<int32_t>(a);
        }
        if (with_attribute)
          attribute_at[i] = r.parse<double>(f[1 + static_cast<size_t>(per)], "an attribute", line);
        at[i] = t;
      },
      [&] {
        if (take)
          take(block, block_regions);
        else if (keep)
          for (const Tet& t : block)
            if (keep(t)) {
              if (pieces.empty() || pieces.back().size() == kPiece) pieces.emplace_back().reserve(kPiece);
              pieces.back().push_back(t);
            }
      });
  counts = {count, found.records};
  if (found.records < count && parts == 1)
    throw FormatError(path + ": file ends after " + std::to_string(found.records) + " of " +
                      std::to_string(count) + " tetrahedra");
  // Tetrahedra past the header's count are not dropped in silence.
  if (found.extra_line)
    r.fail(found.extra_line, "unexpected data after the " + std::to_string(count) + " tetrahedra");
  if (keep) {
    // Reserved room is memory only once written to: it grows as the
    // pieces, each large enough to be a mapping of its own, are returned.
    out.reserve(pieces.empty() ? 0 : (pieces.size() - 1) * kPiece + pieces.back().size());
    for (std::vector<Tet>& piece : pieces) {
      out.insert(out.end(), piece.begin(), piece.end());
      std::vector<Tet>().swap(piece);
    }
  }
  return out;
}

}  // namespace

std::vector<std::array<uint32_t, 4>> read_tetgen_ele(
    const std::string& path, size_t num_points, int index_base,
    const std::function<bool(const std::array<uint32_t, 4>&)>& keep, std::vector<int32_t>* regions,
    std::vector<std::array<uint32_t, 6>>* edge_nodes, std::vector<double>* first_attribute) {
  ElePart counts;
  return read_ele(path, num_points, index_base, keep, regions, 0, 1, counts, {}, edge_nodes, first_attribute);
}

FaceFile read_tetgen_face(const std::string& path, size_t num_points, int index_base) {
  TextRecords r(path);
  TextRecords::Fields tok;
  if (!r.next(tok)) throw FormatError(path + ": empty file, expected a .face header");
  const size_t header = r.line();
  if (tok.empty() || tok.size() > 2)
    r.fail(header, "expected a header '<faces> [<boundary markers: 0 or 1>]'");
  const auto count = r.parse<uint64_t>(tok[0], "a face count", header);
  const int marked = tok.size() > 1 ? r.parse<int>(tok[1], "0 or 1 (boundary markers)", header) : 0;
  if (marked != 0 && marked != 1) r.fail(header, "the boundary marker flag must be 0 or 1");
  FaceFile out;
  for (uint64_t i = 0; i < count; ++i) {
    if (!r.next(tok))
      throw FormatError(path + ": file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                        " faces");
    const size_t line = r.line();
    // The face's number, its 3 (or, -o2, 6) nodes, its marker, and with
    // -nn its two tetrahedra: the count of fields tells the nodes.
    const size_t rest = tok.size() - 1 - static_cast<size_t>(marked);
    if (tok.size() < 1 + static_cast<size_t>(marked) || (rest != 3 && rest != 5 && rest != 6 && rest != 8))
      r.fail(line, "expected a face's number, its 3 or 6 nodes" + std::string(marked ? ", its marker" : "") +
                       " and perhaps its 2 tetrahedra");
    const size_t nodes = rest == 3 || rest == 5 ? 3 : 6;
    std::array<uint32_t, 3> f{};
    for (size_t k = 0; k < 3; ++k) {
      const auto v = r.parse<int64_t>(tok[1 + k], "a vertex index", line) - index_base;
      if (v < 0 || static_cast<uint64_t>(v) >= num_points)
        r.fail(line, "vertex index " + std::string(tok[1 + k]) + " out of range");
      f[k] = static_cast<uint32_t>(v);
    }
    out.faces.push_back(f);
    if (marked) {
      const auto m = r.parse<int64_t>(tok[1 + nodes], "a boundary marker", line);
      if (m < INT32_MIN || m > INT32_MAX) r.fail(line, "a boundary marker out of the 32-bit range");
      out.markers.push_back(static_cast<int32_t>(m));
    }
  }
  if (r.next(tok)) r.fail(r.line(), "unexpected data after the " + std::to_string(count) + " faces");
  return out;
}

ElePart read_tetgen_ele_part(const std::string& path, size_t num_points, int index_base, int part, int parts,
                             bool regions, const EleBlock& take) {
  ElePart counts;
  // (keep: the block's tetrahedra held apart, which `take` then gets; the
  // vector only says that regions are wanted.)
  std::vector<int32_t> wanted;
  read_ele(
      path, num_points, index_base, [](const Tet&) { return false; }, regions ? &wanted : nullptr, part,
      parts, counts, take);
  return counts;
}

}  // namespace dtm
