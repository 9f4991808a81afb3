#include "netgen_vol.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <string_view>
#include <vector>

#include "cell_split.h"
#include "format_error.h"
#include "render_util.h"
#include "second_order.h"
#include "text_cursor.h"

namespace dtm {
namespace {

// The file's text: as it is, or inflated when it is gzip (Netgen saves
// "x.vol.gz" so), in steps, so that memory follows the data present.
std::string vol_text(const std::string& path) {
  std::string bytes = read_whole_file(path);
  if (bytes.size() < 2 || static_cast<unsigned char>(bytes[0]) != 0x1f ||
      static_cast<unsigned char>(bytes[1]) != 0x8b)
    return bytes;
  z_stream z{};
  if (inflateInit2(&z, 15 + 16) != Z_OK) throw FormatError(path + ": cannot start zlib");
  z.next_in = reinterpret_cast<Bytef*>(bytes.data());
  z.avail_in = static_cast<uInt>(std::min<size_t>(bytes.size(), UINT32_MAX));
  std::string out;
  int r = Z_OK;
  while (r == Z_OK) {
    const size_t have = out.size();
    const size_t room = std::max<size_t>(size_t{1} << 20, have / 2);
    out.resize(have + room);
    z.next_out = reinterpret_cast<Bytef*>(out.data() + have);
    z.avail_out = static_cast<uInt>(room);
    r = inflate(&z, Z_NO_FLUSH);
    out.resize(have + room - z.avail_out);
    if (r == Z_BUF_ERROR && z.avail_in == 0) break;  // the input ends inside the stream
    // (A mesh's text inflates some 4-10 times: far more is not one.)
    if (out.size() > (size_t{1} << 20) + 256 * bytes.size()) {
      inflateEnd(&z);
      throw FormatError(path + ": gzip data inflates to more than 256 times its size: not a Netgen mesh");
    }
  }
  inflateEnd(&z);
  if (r != Z_STREAM_END)
    throw FormatError(path + ": gzip data is damaged or truncated (after " + std::to_string(out.size()) +
                      " bytes)" + (z.msg ? std::string(": ") + z.msg : ""));
  return out;
}

// A record's fields, split at blanks, at most `most` (one more: too many).
size_t split(std::string_view line, std::span<std::string_view> out) {
  size_t k = 0, at = 0;
  for (std::string_view f = next_field(line, at); !f.empty() && k < out.size(); f = next_field(line, at))
    out[k++] = f;
  return k;
}

int32_t label(const TextCursor& c, uint64_t i, std::string_view field, const char* what) {
  int64_t v = 0;
  if (!parse_whole(field, v) || v < INT32_MIN || v > INT32_MAX)
    c.fail_line(i, std::string("expected ") + what + ", found '" + std::string(field) + "'");
  return static_cast<int32_t>(v);
}

// An element section's record layout: the integers before the point count
// (what each is; the one at `label` kept), then the points.
struct ElementLayout {
  std::array<const char*, 4> head;  // nullptr after the last
  size_t label;
  const char* what;          // "a volume element"
  int least, most;           // the point counts Netgen writes
  int linear, second_order;  // the point counts of a linear and a second-order element
  bool exact;                // no fields after the points (surface records may carry geometry)
  // The elements read as the tetrahedra or triangles that split them
  // (cell_split.h): by point count, how many are corners (the rest a
  // second-order one's other nodes); 0 for none.
  std::array<uint8_t, 21> split_corners;
};
constexpr std::array<uint8_t, 21> kVolumeSplits = [] {
  std::array<uint8_t, 21> c{};
  c[5] = c[13] = 5;          // pyramids
  c[6] = c[12] = c[15] = 6;  // prisms (12: Netgen's second-order one, its edges on the triangles)
  c[8] = c[20] = 8;          // hexahedra
  return c;
}();
constexpr std::array<uint8_t, 21> kSurfaceSplits = [] {
  std::array<uint8_t, 21> c{};
  c[4] = c[8] = 4;  // quadrilaterals
  return c;
}();
constexpr ElementLayout kVolumeElement{{"a material number", nullptr, nullptr, nullptr},
                                       0,
                                       "a volume element",
                                       4,
                                       20,
                                       4,
                                       10,
                                       true,
                                       kVolumeSplits};
constexpr ElementLayout kSurfaceElement{
    {"a surface number", "a boundary condition number", "a domain number", "a domain number"},
    1,
    "a surface element",
    3,
    8,
    3,
    6,
    false,
    kSurfaceSplits};

// An element read as the tetrahedra or triangles that split it: its points
// (corners first, `corners` of them; in place, at most 20: no allocation
// of its own), its line and its label.
struct SplitElement {
  std::array<uint32_t, 20> points;
  uint8_t count;
  uint8_t corners;
  int32_t label;
  uint64_t line;
  std::span<uint32_t> nodes() { return std::span(points).first(count); }
};

// An element section's records, one a line, read on every core: of each
// linear or second-order element its N corners (1-based, checked against
// the points once they are read) with its line, and its label; of a
// second-order one, its E edge nodes too (in Netgen's order, which is
// kTetEdges': 0 for a linear element's); the elements that are split
// whole to `whole` (1-based, kept apart: there are few); the other
// elements counted.
template <size_t N, size_t E>
void read_elements(TextCursor& c, uint64_t n, const ElementLayout& l,
                   std::vector<std::array<uint32_t, N>>& corners, std::vector<std::array<uint32_t, E>>& edges,
                   std::vector<uint64_t>& lines, std::vector<int32_t>& labels,
                   std::vector<SplitElement>& whole, uint64_t& other) {
  c.rest_of_line();
  const uint64_t first_line = c.mark().line;
  size_t head = 0;
  while (head < l.head.size() && l.head[head]) ++head;
  // (Point numbers in 32 bits: a second-order element's ten take 40 bytes,
  // a linear one's four were 32 as 64-bit numbers.)
  std::vector<std::array<uint32_t, N + E>> read(n);
  std::vector<int32_t> label_of(n);
  std::vector<uint8_t> kind(n);  // 0 linear, 1 second-order, 2 other, 3 split
  const size_t whole_before = whole.size();
  std::mutex split_mutex;
  c.lines(n, [&](uint64_t i, std::string_view line) {
    std::array<std::string_view, 40> f;
    const size_t k = split(line, f);
    if (k < head + 1)
      c.fail_line(i, std::string("expected ") + l.what + "'s numbers, a point count and the points");
    for (size_t h = 0; h < head; ++h) {
      const int32_t v = label(c, i, f[h], l.head[h]);
      if (h == l.label) label_of[i] = v;
    }
    const int32_t np = label(c, i, f[head], "a point count");
    const size_t fields = head + 1 + static_cast<size_t>(std::max(np, 0));
    const bool kind_split = np >= 0 && np <= l.most && l.split_corners[static_cast<size_t>(np)] > 0;
    std::array<uint32_t, 20> points{};
    if (np < l.least || np > l.most || (l.exact ? k != fields : k < fields))
      c.fail_line(i, std::string(l.what) + " of " + std::string(f[head]) + " points needs as many indices");
    for (size_t p = 0; p < static_cast<size_t>(np); ++p) {
      int64_t v = 0;
      if (!parse_whole(f[head + 1 + p], v) || v < 1)
        c.fail_line(i, "expected a point index, found '" + std::string(f[head + 1 + p]) + "'");
      if (v > UINT32_MAX) c.fail_line(i, "point index " + std::string(f[head + 1 + p]) + " out of range");
      if (p < N + E) read[i][p] = static_cast<uint32_t>(v);
      if (kind_split) points[p] = static_cast<uint32_t>(v);
    }
    if (kind_split) {
      const std::lock_guard lock(split_mutex);
      whole.push_back({points, static_cast<uint8_t>(np), l.split_corners[static_cast<size_t>(np)],
                       label_of[i], first_line + i});
    }
    kind[i] = np == l.linear                             ? 0
              : np == l.second_order                     ? 1
              : l.split_corners[static_cast<size_t>(np)] ? 3
                                                         : 2;
  });
  // (In the file's order, whichever core read them.)
  std::sort(whole.begin() + static_cast<std::ptrdiff_t>(whole_before), whole.end(),
            [](const SplitElement& a, const SplitElement& b) { return a.line < b.line; });
  for (uint64_t i = 0; i < n; ++i) {
    other += kind[i] == 2;
    if (kind[i] >= 2) continue;
    std::array<uint32_t, N> corner;
    std::array<uint32_t, E> edge{};
    std::copy_n(read[i].begin(), N, corner.begin());
    if (kind[i] == 1) std::copy_n(read[i].begin() + N, E, edge.begin());
    corners.push_back(corner);
    edges.push_back(edge);
    lines.push_back(first_line + i);
    labels.push_back(label_of[i]);
  }
}

// "number name" records (materials, bcnames), as Netgen reads them: a
// number, then the rest of its line the name (blanks inside it kept; blank
// lines between records skipped). The names by number, the first a number
// is given; a record without a name names nothing.
void read_names(TextCursor& c, uint64_t n, std::map<int32_t, std::string>& names) {
  for (uint64_t i = 0; i < n; ++i) {
    const int64_t number = c.number<int64_t>("a number");
    if (number < INT32_MIN || number > INT32_MAX) c.fail("a number out of the 32-bit range");
    std::string_view name = c.rest_of_line();
    const size_t b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t\r");
    name = b == std::string_view::npos ? std::string_view() : name.substr(b, e - b + 1);
    if (!name.empty()) names.emplace(static_cast<int32_t>(number), std::string(name));
  }
}

// The keywords of the sections read here: a line of another section that is
// one of them means that section's records are not one a line.
bool known_keyword(std::string_view word) {
  for (const char* k : {"points", "volumeelements", "surfaceelements", "surfaceelementsgi",
                        "surfaceelementsuv", "materials", "bcnames", "endmesh", "dimension", "geomtype"})
    if (word == k) return true;
  return false;
}

}  // namespace

InputMesh read_netgen_vol(const std::string& path) {
  TextCursor c(path, vol_text(path), '#');
  if (c.at_end()) c.fail("empty file, expected 'mesh3d'");
  c.expect("mesh3d");
  InputMesh out;
  bool have_points = false;
  uint64_t other_volume = 0, other_faces = 0;
  std::map<std::string, uint64_t> other_records;  // records of other sections, by keyword
  // The elements' corners as read, and each one's line: Netgen writes the
  // elements before the points, so their indices are checked at the end.
  std::vector<std::array<uint32_t, 4>> raw_tets;
  std::vector<std::array<uint32_t, 3>> raw_faces;
  std::vector<std::array<uint32_t, 6>> raw_tet_edges;   // a second-order tetrahedron's edge nodes
  std::vector<std::array<uint32_t, 3>> raw_face_edges;  // and a second-order triangle's
  std::vector<uint64_t> tet_lines, face_lines;
  std::vector<SplitElement> split_volume, split_faces;  // pyramids, prisms, hexahedra; quadrilaterals
  while (true) {
    if (c.at_end()) c.fail("file ends without 'endmesh'");
    const std::string keyword(c.token("a section keyword"));
    // (A number where a section's name should be: the records of the
    // section before, more than its count said.)
    if (keyword.find_first_not_of("0123456789+-.eE") == std::string::npos)
      c.fail("'" + keyword +
             "' where a section keyword should be (a section holds more records than its count)");
    if (keyword == "endmesh") break;
    if (keyword == "dimension") {
      const int dim = c.number<int>("a dimension");
      if (dim != 3) c.fail("a " + std::to_string(dim) + "D mesh: only 3D (volume) meshes are read");
      continue;
    }
    if (keyword == "geomtype") {
      c.number<int>("a geometry type");
      continue;
    }
    if (keyword == "curvedelements") {
      // (Netgen's curved geometry, an archive without a record count: read
      // past up to endmesh.)
      while (!c.at_end() && c.peek() != "endmesh") c.token("curved elements");
      other_records[keyword] += 1;
      continue;
    }
    // The fewest bytes a record takes: no section claims more records than
    // the file can hold before they are read.
    const uint64_t least = keyword == "points"                        ? 6
                           : keyword == "volumeelements"              ? 12
                           : keyword.rfind("surfaceelements", 0) == 0 ? 16
                                                                      : 2;
    const uint64_t n = c.count("a record count", c.remaining() / least);
    if (keyword == "points") {
      if (have_points) c.fail("a second 'points' section");
      have_points = true;
      c.rest_of_line();
      out.points.resize(n);
      c.lines(n, [&](uint64_t i, std::string_view line) {
        std::array<std::string_view, 4> f;
        double xyz[3] = {0, 0, 0};
        if (split(line, f) != 3) c.fail_line(i, "expected the 3 coordinates of a point");
        for (int a = 0; a < 3; ++a)
          if (!parse_whole(f[static_cast<size_t>(a)], xyz[a]) || !std::isfinite(xyz[a]))
            c.fail_line(
                i, "coordinate is not a finite number: '" + std::string(f[static_cast<size_t>(a)]) + "'");
        out.points[i] = {xyz[0], xyz[1], xyz[2]};
      });
      continue;
    }
    if (keyword == "volumeelements") {
      read_elements<4, 6>(c, n, kVolumeElement, raw_tets, raw_tet_edges, tet_lines, out.tet_regions,
                          split_volume, other_volume);
      continue;
    }
    if (keyword == "surfaceelements" || keyword == "surfaceelementsgi" || keyword == "surfaceelementsuv") {
      read_elements<3, 3>(c, n, kSurfaceElement, raw_faces, raw_face_edges, face_lines, out.face_tags,
                          split_faces, other_faces);
      continue;
    }
    if (keyword == "materials") {
      read_names(c, n, out.region_names);
      continue;
    }
    if (keyword == "bcnames") {
      read_names(c, n, out.face_tag_names);
      continue;
    }
    if (keyword == "identificationtypes") {
      // (Netgen writes its n types on one line.)
      for (uint64_t i = 0; i < n; ++i) c.number<int64_t>("an identification type");
      if (n > 0) other_records[keyword] += n;
      continue;
    }
    // Any other section (edge segments, face colours, identifications,
    // singular points, codimension names, ...): its records, one a line,
    // as Netgen writes them; one that is not ends with an error, not with
    // the next section taken for its records.
    c.rest_of_line();
    c.lines(n, [&](uint64_t i, std::string_view line) {
      size_t at = 0;
      const std::string_view first = next_field(line, at);
      if (known_keyword(first))
        c.fail_line(i, "section '" + keyword + "' ends before its " + std::to_string(n) +
                           " records (its records are not one a line)");
    });
    if (n > 0) other_records[keyword] += n;
  }
  if (!have_points) c.fail("'endmesh' without a 'points' section");
  // The elements' corners, checked against the points.
  const uint64_t points = out.points.size();
  const auto corner = [&](int64_t v, uint64_t line) {
    if (static_cast<uint64_t>(v) > points)
      throw FormatError(path + ":" + std::to_string(line) + ": point index " + std::to_string(v) +
                        " out of range 1.." + std::to_string(points));
    return static_cast<uint32_t>(v - 1);
  };
  out.tets.reserve(raw_tets.size());
  for (size_t t = 0; t < raw_tets.size(); ++t) {
    const auto& v = raw_tets[t];
    const uint64_t line = tet_lines[t];
    out.tets.push_back({corner(v[0], line), corner(v[1], line), corner(v[2], line), corner(v[3], line)});
    if (const auto& e = raw_tet_edges[t]; e[0] != 0) {
      std::array<uint32_t, 6> edge;
      for (size_t k = 0; k < 6; ++k) edge[k] = corner(e[k], line);
      add_tet_edge_nodes(out, edge);
    }
  }
  out.tagged_faces.reserve(raw_faces.size());
  for (size_t f = 0; f < raw_faces.size(); ++f) {
    const auto& v = raw_faces[f];
    const uint64_t line = face_lines[f];
    out.tagged_faces.push_back({corner(v[0], line), corner(v[1], line), corner(v[2], line)});
    if (const auto& e = raw_face_edges[f]; e[0] != 0)
      for (uint32_t node : e) out.other_edge_nodes.push_back(corner(node, line));
  }
  // The pyramids, prisms, hexahedra and quadrilaterals as the tetrahedra
  // and triangles that split them (cell_split.h), each with its element's
  // label: after the file's own, as gmsh's are.
  std::map<size_t, uint64_t> split_cells;  // by corners
  for (auto* elements : {&split_volume, &split_faces})
    for (SplitElement& e : *elements) {
      for (uint32_t& v : e.nodes()) v = corner(v, e.line);
      const size_t added = add_split_cell(e.nodes(), e.corners, out);
      // (Turned as Netgen turns its own tetrahedra, the other way from
      // split_cell()'s: --exact wants one orientation throughout.)
      if (e.corners > 4)
        for (size_t t = out.tets.size() - added; t < out.tets.size(); ++t)
          std::swap(out.tets[t][0], out.tets[t][1]);
      auto& labels = e.corners == 4 ? out.face_tags : out.tet_regions;
      labels.insert(labels.end(), added, e.label);
      if (e.corners > 4) ++split_cells[e.corners];
    }
  if (!out.tets.empty()) out.region_source = "materials (Netgen domains)";
  if (!out.tagged_faces.empty()) out.face_tag_source = "surface elements' boundary conditions (Netgen bcnr)";
  // (Second-order elements are read as linear ones: second_order.h.)
  if (!split_cells.empty()) out.left_out.push_back(split_cells_note(split_cells));
  if (other_volume > 0)
    out.left_out.push_back(std::to_string(other_volume) +
                           " volume elements that are not tetrahedra (4 or 10 nodes), pyramids (5, 13), "
                           "prisms (6, 12, 15) or hexahedra (8, 20)");
  if (other_faces > 0)
    out.left_out.push_back(
        std::to_string(other_faces) +
        " surface elements that are not triangles (3 or 6 nodes) or quadrilaterals (4, 8)");
  if (!other_records.empty()) {
    std::string list;
    for (const auto& [keyword, count] : other_records)
      list += (list.empty() ? "" : ", ") + std::to_string(count) + " " + keyword;
    out.left_out.push_back(
        "sections other than points, volumeelements, surfaceelements, materials and "
        "bcnames (" +
        list + ")");
  }
  if (!c.at_end()) out.left_out.push_back("what follows 'endmesh' (Netgen's geometry)");
  return out;
}

namespace {

// A name as one word (Netgen reads names with >>).
std::string one_word(std::string name) {
  for (char& ch : name)
    if (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r') ch = '_';
  return name.empty() ? "_" : name;
}

}  // namespace

std::vector<std::string> netgen_renumbering(const OutputMesh& m) {
  std::vector<std::string> out;
  std::vector<int32_t> labels(m.region.begin(), m.region.end());
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  for (size_t d = 0; d < labels.size(); ++d)
    if (labels[d] != static_cast<int32_t>(d) + 1)
      out.push_back("region " + std::to_string(labels[d]) + " as material " + std::to_string(d + 1) +
                    " (Netgen numbers its domains 1, 2, ...)");
  const auto said = [&](const std::string& what, const std::map<int32_t, std::string>& names) {
    for (const auto& [label, name] : names)
      if (one_word(name) != name)
        out.push_back(what + " " + std::to_string(label) + "'s name \"" + name + "\" as " + one_word(name) +
                      " (a Netgen name is one word)");
  };
  if (!m.region.empty()) said("region", m.region_names);
  // (The faces' numbers are their tags where the tags are 1 to K, each on
  // one pair of domains; else one number per tag and pair, render_netgen_vol.)
  std::set<int32_t> tags(m.face_tags.begin(), m.face_tags.end());
  if (!tags.empty() && (*tags.begin() != 1 || *tags.rbegin() != static_cast<int32_t>(tags.size())))
    out.push_back(
        "the face tags as Netgen boundary condition numbers 1 to K, one per tag and pair of domains "
        "(their names stay with them)");
  said("face tag", m.face_tag_names);
  return out;
}

std::string render_netgen_vol(const OutputMesh& m) {
  using Face = std::array<uint32_t, 3>;
  // The regions as Netgen's domains 1..K, in the labels' order.
  std::vector<int32_t> labels(m.region.begin(), m.region.end());
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const auto domain = [&](size_t cell) -> int {
    if (m.region.empty()) return 1;
    return 1 +
           static_cast<int>(std::lower_bound(labels.begin(), labels.end(), m.region[cell]) - labels.begin());
  };
  // The surface: each face of one cell, or of two cells of two domains
  // (then from the lower's side), turned to face away from its cell.
  struct Side {
    Face sorted;
    uint32_t cell;
    uint8_t corner;  // the cell's corner the face does not have
  };
  std::vector<Side> sides;
  sides.reserve(m.cells.size() * 4);
  for (uint32_t c = 0; c < m.cells.size(); ++c)
    for (uint8_t k = 0; k < 4; ++k) {
      Face f;
      for (uint8_t i = 0, j = 0; i < 4; ++i)
        if (i != k) f[j++] = m.cells[c][i];
      std::sort(f.begin(), f.end());
      sides.push_back({f, c, k});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
    return a.sorted != b.sorted ? a.sorted < b.sorted : a.cell < b.cell;
  });
  std::map<Face, int32_t> tag_of;  // the tagged faces' tags
  for (size_t f = 0; f < m.faces.size(); ++f) {
    Face key = m.faces[f];
    std::sort(key.begin(), key.end());
    tag_of.emplace(key, m.face_tags[f]);
  }
  struct Element {
    int64_t tag;  // kUntagged: none
    int domin, domout;
    Face corners;
  };
  constexpr int64_t kUntagged = int64_t{INT32_MAX} + 1;
  std::vector<Element> surface;
  for (size_t i = 0; i < sides.size();) {
    size_t j = i + 1;
    while (j < sides.size() && sides[j].sorted == sides[i].sorted) ++j;
    const Side* in = &sides[i];
    int domout = 0;
    const auto tag = tag_of.find(sides[i].sorted);
    if (j - i == 2) {
      const int a = domain(sides[i].cell), b = domain(sides[i + 1].cell);
      // (A face inside a domain is a surface element only when tagged:
      // Netgen keeps such faces with the domain on both sides.)
      if (a == b && tag == tag_of.end()) {
        i = j;
        continue;
      }
      if (b < a) in = &sides[i + 1];
      domout = std::max(a, b);
    }
    // The cell's corners without `corner`, in an order whose normal points
    // away from it (Netgen's: out of domin). Our cells are positively
    // oriented: (1,2,3) from corner 0 faces away; each other corner's face
    // follows by an even permutation.
    static constexpr std::array<std::array<uint8_t, 3>, 4> kAway = {
        {{{1, 2, 3}}, {{0, 3, 2}}, {{0, 1, 3}}, {{0, 2, 1}}}};
    const auto& cell = m.cells[in->cell];
    const auto& order = kAway[in->corner];
    surface.push_back({tag == tag_of.end() ? kUntagged : int64_t{tag->second},
                       domain(in->cell),
                       domout,
                       {cell[order[0]], cell[order[1]], cell[order[2]]}});
    i = j;
  }
  // One number a kind of face (its tag and its two domains), in the order
  // the kinds first appear: Netgen makes a face descriptor of each kind in
  // that order, and Netgen 6.2 names face descriptor i by the i-th name of
  // bcnames where later versions name boundary condition b by the b-th:
  // with surfnr = bcnr = the descriptor's number, both read the same names.
  std::map<std::array<int64_t, 3>, int> kind_number;
  std::vector<int64_t> kind_tag;  // per number - 1
  for (const Element& e : surface)
    if (kind_number.emplace(std::array<int64_t, 3>{e.tag, e.domin, e.domout}, kind_tag.size() + 1).second)
      kind_tag.push_back(e.tag);
  // Where the tags are 1 to K, one kind each (a Netgen mesh's own boundary
  // condition numbers, say), each kind is numbered by its tag, and the
  // elements go in that order, so that the descriptors Netgen makes come
  // in it too: the file's numbers are the stream's tags.
  std::vector<int64_t> tags_in_order = kind_tag;
  std::sort(tags_in_order.begin(), tags_in_order.end());
  bool numbered = true;
  for (size_t k = 0; k < tags_in_order.size() && numbered; ++k) numbered = tags_in_order[k] == int64_t(k) + 1;
  if (numbered && !tags_in_order.empty()) {
    for (auto& [kind, number] : kind_number) number = static_cast<int>(kind[0]);
    kind_tag = tags_in_order;
    std::stable_sort(surface.begin(), surface.end(),
                     [](const Element& a, const Element& b) { return a.tag < b.tag; });
  }

  std::string out =
      "mesh3d\ndimension\n3\ngeomtype\n0\n\n# surfnr    bcnr   domin  domout      np      p1      p2      "
      "p3\n"
      "surfaceelements\n";
  append_number(out, surface.size());
  out += '\n';
  append_lines(out, surface.size(), [&](size_t f, std::string& line) {
    const Element& e = surface[f];
    const int64_t kind = kind_number.at({e.tag, e.domin, e.domout});
    for (const int64_t v : {kind, kind, int64_t{e.domin}, int64_t{e.domout}, int64_t{3}}) {
      line += ' ';
      append_number(line, v);
    }
    for (uint32_t v : e.corners) {
      line += ' ';
      append_number(line, uint64_t{v} + 1);
    }
    line += '\n';
  });
  out += "\n#  matnr      np      p1      p2      p3      p4\nvolumeelements\n";
  append_number(out, m.cells.size());
  out += '\n';
  // Netgen's tetrahedra turn the other way: two corners swapped.
  append_lines(out, m.cells.size(), [&](size_t c, std::string& line) {
    append_number(line, domain(c));
    line += " 4";
    const auto& t = m.cells[c];
    for (uint32_t v : {t[1], t[0], t[2], t[3]}) {
      line += ' ';
      append_number(line, uint64_t{v} + 1);
    }
    line += '\n';
  });
  out += "\n#          X             Y             Z\npoints\n";
  append_number(out, m.points.size());
  out += '\n';
  append_lines(out, m.points.size(),
               [&](size_t v, std::string& line) { append_xyz_line(line, m.grid.to_input(m.points[v])); });
  out += "\nmaterials\n";
  const size_t domains = m.region.empty() ? 1 : labels.size();
  append_number(out, domains);
  out += '\n';
  for (size_t d = 0; d < domains; ++d) {
    append_number(out, d + 1);
    out += ' ';
    if (m.region.empty()) {
      out += "default";
    } else {
      const auto name = m.region_names.find(labels[d]);
      out += one_word(name != m.region_names.end() ? name->second : "region_" + std::to_string(labels[d]));
    }
    out += '\n';
  }
  // Each kind's name: its tag's, "bc_" and its label, or "default" for
  // the faces without a tag.
  out += "\nbcnames\n";
  append_number(out, kind_tag.size());
  out += '\n';
  for (size_t k = 0; k < kind_tag.size(); ++k) {
    append_number(out, k + 1);
    out += ' ';
    if (kind_tag[k] == kUntagged) {
      out += "default";
    } else {
      const auto name = m.face_tag_names.find(static_cast<int32_t>(kind_tag[k]));
      out += one_word(name != m.face_tag_names.end() ? name->second : "bc_" + std::to_string(kind_tag[k]));
    }
    out += '\n';
  }
  out += "\nendmesh\n";
  return out;
}

}  // namespace dtm
