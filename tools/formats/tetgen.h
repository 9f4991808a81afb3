// TetGen .node / .ele files (https://wias-berlin.de/software/tetgen/fformats.html):
// '#' comments, a header line, then one numbered record per line. Indices may
// start at 0 or 1 (the first record decides, as TetGen does).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "common/grid.h"
#include "format_error.h"

namespace dtm {

struct NodeFile {
  std::vector<InputPoint> points;
  std::vector<int> markers;  // boundary markers when the file has them, else empty
  int index_base = 0;        // index of the first point (0 or 1)
  // The points' attributes, `attribute_count` per point, point after point.
  int attribute_count = 0;
  std::vector<double> attributes;
};

NodeFile read_tetgen_node(const std::string& path);

// Part `part` of `parts` of a .node's points (an MPI rank's range of the
// file, TextRecords::keep_to_part()), errors named by their line in the
// whole file. Each record's index must follow the part's first record's;
// whether that one follows the parts before it, and whether the parts hold
// the header's count, only the parts joined can tell (the caller checks,
// fail_at_node_record() names the line). first_index is the part's first
// index (node.index_base, an int, is left 0).
struct NodePart {
  uint64_t header_count = 0;
  bool has_markers = false;
  int64_t first_index = -1;  // the index of the part's first point; -1 if it holds none
  NodeFile node;             // the part's points, their attributes and markers
};
NodePart read_tetgen_node_part(const std::string& path, int part, int parts);
// Throws FormatError("path:LINE: problem"), LINE that of record `record`
// (0: the first) of part `part` of `parts` (re-read to find it).
[[noreturn]] void fail_at_node_record(const std::string& path, int part, int parts, uint64_t record,
                                      const std::string& problem);

// The attributes per tetrahedron an .ele's header announces (TetGen's
// region attribute, -A), 0 if none.
int tetgen_ele_attributes(const std::string& path);

// Tetrahedra of an .ele file as 0-based indices into the .node's points.
// `index_base` is the first index of the matching .node file.
// `keep`, when given, chooses the tetrahedra to hold (each is checked all
// the same): an MPI rank holds its share of a large mesh only.
// `regions`, when given (and no `keep`), receives each tetrahedron's first
// attribute, TetGen's region (an integer), if the file has attributes.
// A second-order .ele (10 nodes per tetrahedron, TetGen -o2) is read as its
// linear tetrahedra with each one's edge nodes in `edge_nodes` (in
// kTetEdges' order, second_order.h), which must then be given (and no
// `keep`); refused otherwise. With `first_attribute` (and no `keep`), the
// first attribute is read into it as it is, a real number (TetGen's
// regional attributes are), and `regions` is left alone.
std::vector<std::array<uint32_t, 4>> read_tetgen_ele(
    const std::string& path, size_t num_points, int index_base = 0,
    const std::function<bool(const std::array<uint32_t, 4>&)>& keep = {},
    std::vector<int32_t>* regions = nullptr, std::vector<std::array<uint32_t, 6>>* edge_nodes = nullptr,
    std::vector<double>* first_attribute = nullptr);

// A .face file's faces (TetGen -p writes the boundary's, -f every face) as
// 0-based indices into the .node's points, and their boundary markers
// (empty when the file has none: its header's second number 0). A
// second-order file's (-o2: 6 nodes a face) and one with the adjacent
// tetrahedra (-nn: 2 more numbers a line) read the same.
struct FaceFile {
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<int32_t> markers;
};
FaceFile read_tetgen_face(const std::string& path, size_t num_points, int index_base);

// Part `part` of `parts` of an .ele's records (an MPI rank's range of the
// file, TextRecords::keep_to_part()): passed to `take` a block at a time,
// in file order, on the calling thread, with each one's region (its first
// attribute, TetGen -A; none when the file has no attributes or `regions`
// is false); errors named by their line in the whole file.
// Returns the header's count of tetrahedra and the part's; the parts'
// counts must add up to the header's (the caller checks, having them all).
struct ElePart {
  uint64_t header_count = 0;
  uint64_t records = 0;
};
using EleBlock = std::function<void(std::span<const std::array<uint32_t, 4>>, std::span<const int32_t>)>;
ElePart read_tetgen_ele_part(const std::string& path, size_t num_points, int index_base, int part, int parts,
                             bool regions, const EleBlock& take);

}  // namespace dtm
