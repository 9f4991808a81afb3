// The only file that instantiates CGAL's point-set readers.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/Point_set_3.h>
#include <CGAL/Point_set_3/IO/OFF.h>
#include <CGAL/Point_set_3/IO/PLY.h>
#include <CGAL/Point_set_3/IO/XYZ.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <type_traits>

#include "format_error.h"
#include "point_set_text.h"
#include "point_sets.h"
#include "text_cursor.h"

namespace dtm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using PointSet = CGAL::Point_set_3<Kernel::Point_3, Kernel::Vector_3>;

// The file's type of a property held as T.
template <class T>
constexpr ScalarType scalar_type_of() {
  if constexpr (std::is_same_v<T, int8_t>) return ScalarType::kInt8;
  if constexpr (std::is_same_v<T, uint8_t>) return ScalarType::kUInt8;
  if constexpr (std::is_same_v<T, int16_t>) return ScalarType::kInt16;
  if constexpr (std::is_same_v<T, uint16_t>) return ScalarType::kUInt16;
  if constexpr (std::is_same_v<T, int32_t>) return ScalarType::kInt32;
  if constexpr (std::is_same_v<T, uint32_t>) return ScalarType::kUInt32;
  if constexpr (std::is_same_v<T, float>) return ScalarType::kFloat32;
  return ScalarType::kFloat64;
}

// The property `name` as a field, in the type the file stores, if it has
// type T.
template <class T>
bool take_property(const PointSet& ps, const std::string& name, InputMesh& out) {
  const auto [map, found] = ps.template property_map<T>(name);
  if (!found) return false;
  VertexField f{name, 1, {}};
  f.type = scalar_type_of<T>();
  f.values.reserve(ps.size());
  for (const auto& index : ps) f.values.push_back(static_cast<double>(map[index]));
  out.fields.push_back(std::move(f));
  return true;
}

// `lists`: the vertex properties the file's header declares as lists
// (named by the caller, once).
InputMesh from_point_set(const PointSet& ps, const std::set<std::string>& lists) {
  InputMesh out;
  out.points.reserve(ps.size());
  for (const auto& index : ps) {
    const auto& p = ps.point(index);
    out.points.push_back({p.x(), p.y(), p.z()});
  }
  if (ps.has_normal_map()) {
    VertexField f{"normal", 3, {}};
    for (const auto& index : ps) {
      const auto& n = ps.normal(index);
      f.values.insert(f.values.end(), {n.x(), n.y(), n.z()});
    }
    out.fields.push_back(std::move(f));
  }
  for (const std::string& name : ps.properties()) {
    if (name == "index" || name == "point" || name == "normal") continue;
    const bool taken = take_property<int8_t>(ps, name, out) || take_property<uint8_t>(ps, name, out) ||
                       take_property<int16_t>(ps, name, out) || take_property<uint16_t>(ps, name, out) ||
                       take_property<int32_t>(ps, name, out) || take_property<uint32_t>(ps, name, out) ||
                       take_property<float>(ps, name, out) || take_property<double>(ps, name, out);
    if (!taken && !lists.contains(name))
      out.left_out.push_back("the point property '" + name + "' (not a number per point)");
  }
  return out;
}

const char* name_of(PointSetFormat f) {
  switch (f) {
    case PointSetFormat::kPly:
      return "PLY";
    case PointSetFormat::kOff:
      return "OFF";
    case PointSetFormat::kObj:
      return "OBJ";
    case PointSetFormat::kXyz:
      return "XYZ";
  }
  return "?";
}

// What each reader expects, for the error message (CGAL gives no position).
const char* expectations(PointSetFormat f) {
  switch (f) {
    case PointSetFormat::kPly:
      return "a 'ply' header ending in 'end_header', a vertex element with x y z, and as many items as the "
             "header announces";
    case PointSetFormat::kOff:
      return "an 'OFF' header, the vertex, face and edge counts, then as many 'x y z' lines as announced";
    case PointSetFormat::kObj:
      return "'v x y z' vertex lines (and optional faces)";
    case PointSetFormat::kXyz:
      return "one 'x y z' (or 'x y z nx ny nz') line per point";
  }
  return "";
}

// A surface's faces: its points are the input, its solid is carved by alpha.
std::string faces_note(uint64_t faces) {
  return std::to_string(faces) +
         " faces (a surface's points are coded, the solid carved by alpha; its faces are "
         "not read)";
}

// CGAL's OFF point reader stops quietly at the end of the file, however many
// vertices the header announced: compare with the header ourselves. The
// faces it announces, which a point set does not read, are named.
void check_off_count(const std::string& path, size_t read, std::vector<std::string>& left_out) {
  TextCursor c = TextCursor::open(path, '#');
  const std::string_view header = c.token("an OFF header");
  if (header.size() < 3 || header.substr(header.size() - 3) != "OFF")
    return;  // CGAL accepted it: leave it be
  const auto announced = c.number<uint64_t>("a vertex count");
  if (announced != read)
    throw FormatError(path + ": the header announces " + std::to_string(announced) +
                      " vertices, the file holds " + std::to_string(read) + " (truncated?)");
  if (const auto faces = c.number<uint64_t>("a face count"); faces > 0) left_out.push_back(faces_note(faces));
}

// CGAL's PLY reader trusts its header: a 'property' line before any
// 'element' line makes it index an empty vector, and a vertex coordinate
// (x y z, nx ny nz) that is not float or double makes it call through a null
// pointer (undefined behaviour, both found by fuzzing); an element count is
// reserved as announced (a few bytes can announce 4 billion vertices). The
// header is checked here first; the data stays CGAL's to read.
// What the header says beside the checks.
struct PlyHeader {
  bool by_meshdec = false;             // meshdec wrote the file (its comment line)
  std::set<std::string> vertex_lists;  // the vertex element's list properties
  bool float_normals = false;          // nx is a float (CGAL holds normals as doubles)
  std::vector<std::string> left_out;   // what a point set does not read, named
  bool ascii = false;                  // format ascii 1.0
  std::vector<std::string> elements;   // in the header's order
  uint64_t vertices = 0;               // the vertex element's count
  size_t vertex_properties = 0;
};

PlyHeader check_ply_header(const std::string& path) {
  PlyHeader read;
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const auto file_size = static_cast<uint64_t>(std::max<std::streamoff>(0, in.tellg()));
  in.seekg(0);
  skip_byte_order_mark(in);
  auto is_name = [](const std::string& w) {
    return !w.empty() &&
           std::all_of(w.begin(), w.end(), [](unsigned char ch) { return std::isalnum(ch) || ch == '_'; });
  };
  std::string line, element;
  std::set<std::string> property_names;  // "element.property"
  int vertex_elements = 0, coordinates = 0;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = path + ":" + std::to_string(number) + ": ";
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (number == 1) {
      if (keyword != "ply") throw FormatError(where + "not a PLY file (the first line must be 'ply')");
      continue;
    }
    if (keyword == "end_header") {
      if (vertex_elements != 1 || coordinates != 3)
        throw FormatError(path + ": the PLY header needs one 'vertex' element with float or double x, y, z");
      for (const std::string& name : read.vertex_lists)
        read.left_out.push_back("the point property '" + name + "' (a list, not a number per point)");
      return read;
    }
    if (keyword == "comment" && line.rfind("comment written by dtmesh", 0) == 0) read.by_meshdec = true;
    if (keyword == "format") read.ascii = line.rfind("format ascii", 0) == 0;
    if (keyword == "comment" || keyword == "obj_info" || keyword == "format") continue;
    if (keyword == "element") {
      std::string name, count_text, extra;
      if (!(words >> name >> count_text) || (words >> extra) || !is_name(name) ||
          !std::all_of(count_text.begin(), count_text.end(),
                       [](unsigned char ch) { return std::isdigit(ch); }) ||
          count_text.size() > 19)
        throw FormatError(where + "an 'element' line is 'element NAME COUNT'");
      const uint64_t count = std::stoull(count_text);
      if (count > file_size)
        throw FormatError(where + "element '" + name + "' announces " + count_text +
                          " items; the file has only " + std::to_string(file_size) + " bytes");
      element = name;
      read.elements.push_back(name);
      if (name == "vertex") read.vertices = count;
      if (name == "vertex")
        ++vertex_elements;
      else if (count > 0)
        read.left_out.push_back(name == "face" ? faces_note(count)
                                               : "the element '" + name + "' (" + count_text + " items)");
    } else if (keyword == "property") {
      if (element.empty()) throw FormatError(where + "'property' before any 'element'");
      std::string type, name, item_type, extra;
      words >> type;
      if (type == "list") words >> item_type >> type;
      words >> name;
      if (!is_name(type) || !is_name(name) || (!item_type.empty() && !is_name(item_type)) || (words >> extra))
        throw FormatError(
            where + "a 'property' line is 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      if (!property_names.insert(element + "." + name).second)
        throw FormatError(where + "element '" + element + "' has two properties named '" + name + "'");
      const bool coordinate =
          name == "x" || name == "y" || name == "z" || name == "nx" || name == "ny" || name == "nz";
      const bool real = item_type.empty() &&  // a list is not a coordinate
                        (type == "float" || type == "float32" || type == "double" || type == "float64");
      if (element == "vertex" && coordinate && !real)
        throw FormatError(where + "vertex property '" + name + "' is '" + type +
                          "'; coordinates must be float or double");
      if (element == "vertex" && (name == "x" || name == "y" || name == "z")) ++coordinates;
      if (element == "vertex") ++read.vertex_properties;
      if (element == "vertex" && !item_type.empty()) read.vertex_lists.insert(name);
      if (element == "vertex" && name == "nx") read.float_normals = type == "float" || type == "float32";
    } else {
      throw FormatError(where + "unknown PLY header line '" + line.substr(0, 40) + "'");
    }
  }
  throw FormatError(path + ": the PLY header has no 'end_header' line");
}

// std::cerr held while CGAL reads: its readers print what stopped them
// there, which our message then carries (not two messages, one of them
// without the tool's name).
class HeldCerr {
 public:
  HeldCerr() : was_(std::cerr.rdbuf(said_.rdbuf())) {}
  ~HeldCerr() { std::cerr.rdbuf(was_); }
  HeldCerr(const HeldCerr&) = delete;
  HeldCerr& operator=(const HeldCerr&) = delete;
  // The first line said, or nothing.
  std::string first_line() const {
    const std::string s = said_.str();
    const size_t start = s.find_first_not_of(" \t\r\n");
    if (start == std::string::npos) return {};
    return s.substr(start, s.find('\n', start) - start);
  }

 private:
  std::ostringstream said_;
  std::streambuf* was_;
};

}  // namespace

InputMesh read_point_set(const std::string& path, PointSetFormat format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot open file");
  if (in.peek() == std::ifstream::traits_type::eof()) throw FormatError(path + ": empty file");
  skip_byte_order_mark(in);
  InputMesh out;
  bool ok = false;
  PlyHeader ply;
  std::vector<std::string> left_out;
  std::string cgal_said;
  {
    const HeldCerr held;
    if (format == PointSetFormat::kObj) {
      std::vector<Kernel::Point_3> points;
      std::vector<std::vector<std::size_t>> faces;
      ok = CGAL::IO::read_OBJ(in, points, faces, CGAL::parameters::verbose(false));
      // CGAL wants a polygon soup and refuses an OBJ without faces, after
      // reading it whole; a point cloud is what we want here.
      if (!ok && faces.empty() && !points.empty() && in.eof() && !in.bad()) ok = true;
      for (const auto& p : points) out.points.push_back({p.x(), p.y(), p.z()});
      for (const auto& f : faces)
        for (std::size_t v : f)
          if (v >= points.size())
            throw FormatError(path + ": a face names vertex " + std::to_string(v + 1) + " of " +
                              std::to_string(points.size()));
      if (!faces.empty()) left_out.push_back(faces_note(faces.size()));
    } else {
      PointSet ps;
      switch (format) {
        case PointSetFormat::kPly:
          ply = check_ply_header(path);
          ok = CGAL::IO::read_PLY(in, ps);
          break;
        case PointSetFormat::kOff:
          ok = CGAL::IO::read_OFF(in, ps);
          break;
        default:
          ok = CGAL::IO::read_XYZ(in, ps);
          break;
      }
      if (ok) out = from_point_set(ps, ply.vertex_lists);
    }
    cgal_said = held.first_line();
  }
  if (ok && format == PointSetFormat::kOff) check_off_count(path, out.points.size(), left_out);
  if (!ok)
    throw FormatError(path + ": not a valid " + std::string(name_of(format)) +
                      " file (CGAL's reader stopped" +
                      (cgal_said.empty() ? std::string() : ": \"" + cgal_said + "\"") + "; expected " +
                      expectations(format) + ")");
  // (CGAL's parsing passes over what the text holds beyond each vertex's
  // numbers: read again, line by line.)
  const bool ply_lines =
      ply.ascii && !ply.elements.empty() && ply.elements.front() == "vertex" && ply.vertex_lists.empty();
  const PlyVertexLines vertex_lines{ply.vertices, ply.vertex_properties, ply.elements.size() == 1};
  check_point_set_text(path, format, out.points.size(), ply_lines ? &vertex_lines : nullptr, left_out);
  if (out.points.empty()) throw FormatError(path + ": no vertices");
  // A surface meshdec wrote carries its own 'level' (each vertex's coarsest
  // level), which a decoder makes again: not a field of the input's (else a
  // decoded mesh would hold two).
  if (ply.by_meshdec && std::erase_if(out.fields, [](const VertexField& f) { return f.name == "level"; }) > 0)
    out.left_out.push_back("the point property 'level' (meshdec's own: the decoder makes it again)");
  if (ply.float_normals)
    for (VertexField& f : out.fields)
      if (f.name == "normal") f.type = ScalarType::kFloat32;
  out.left_out.insert(out.left_out.end(), ply.left_out.begin(), ply.left_out.end());
  out.left_out.insert(out.left_out.end(), left_out.begin(), left_out.end());
  for (size_t i = 0; i < out.points.size(); ++i) {
    const InputPoint& p = out.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw FormatError(path + ": vertex " + std::to_string(i) + ": coordinate is not finite");
  }
  return out;
}

}  // namespace dtm
