// libexodusii's files and the element tables (exodus_file.h).
#include "exodus_file.h"

#include <exodusII.h>
#include <netcdf.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <set>
#include <stdexcept>

#include "format_error.h"
#include "netcdf_header.h"

namespace dtm::exodus {
namespace {

// libexodusii's last message, for ours.
std::string last_error() {
  const char* msg = nullptr;
  const char* func = nullptr;
  int code = 0;
  ex_get_err(&msg, &func, &code);
  std::string out = msg && *msg ? msg : "";
  if (out.empty() && code != 0) out = "error " + std::to_string(code);
  return out;
}

// The dimensions (by name) of the variables libexodusii 6.02 reads whole
// (nc_get_var) into buffers its caller sizes from those dimensions; none
// for the others (the variables' values and the times it reads in the
// ranges it is asked for, which netCDF checks).
std::vector<std::string> exodus_dimensions(const std::string& variable) {
  // Whether the name is `prefix` and a number, and the number.
  const auto numbered = [&](const std::string& prefix) {
    if (variable.rfind(prefix, 0) != 0 || variable.size() == prefix.size() ||
        variable.find_first_not_of("0123456789", prefix.size()) != std::string::npos)
      return std::string();
    return variable.substr(prefix.size());
  };
  if (variable == "coordx" || variable == "coordy" || variable == "coordz") return {"num_nodes"};
  if (variable == "coord") return {"num_dim", "num_nodes"};
  if (variable == "eb_status" || !numbered("eb_prop").empty()) return {"num_el_blk"};
  if (variable == "ns_status" || !numbered("ns_prop").empty()) return {"num_node_sets"};
  if (variable == "ss_status" || !numbered("ss_prop").empty()) return {"num_side_sets"};
  if (variable == "node_num_map") return {"num_nodes"};
  if (variable == "elem_num_map") return {"num_elem"};
  if (variable == "elem_var_tab") return {"num_el_blk", "num_elem_var"};
  if (const auto n = numbered("connect"); !n.empty()) return {"num_el_in_blk" + n, "num_nod_per_el" + n};
  if (const auto n = numbered("elem_ss"); !n.empty()) return {"num_side_ss" + n};
  if (const auto n = numbered("side_ss"); !n.empty()) return {"num_side_ss" + n};
  if (const auto n = numbered("node_ns"); !n.empty()) return {"num_nod_ns" + n};
  return {};
}

// Before libexodusii 6.02 opens a file:
// * the variables it reads whole must have the shape of the dimensions
//   that size its caller's buffers (a file that declares `connect1` over
//   more elements than num_el_in_blk1 would have it write past them);
// * the attributes it reads into buffers of a fixed size without looking
//   at their length (a block's elem_type into 33 bytes, a property's name
//   likewise, a global attribute such as file_size into one number) must
//   fit them.
void check_variables_and_attributes(const std::string& path) {
  int nc = -1;
  if (nc_open(path.c_str(), NC_NOWRITE, &nc) != NC_NOERR) return;  // (ex_open says why)
  struct Closer {
    int id;
    ~Closer() { nc_close(id); }
  } closer{nc};
  int variables = 0;
  if (nc_inq_nvars(nc, &variables) != NC_NOERR) return;
  for (int v = 0; v < variables; ++v) {
    char name[NC_MAX_NAME + 1] = {};
    int dimensions = 0;
    if (nc_inq_varname(nc, v, name) != NC_NOERR || nc_inq_varndims(nc, v, &dimensions) != NC_NOERR) continue;
    const std::vector<std::string> expected = exodus_dimensions(name);
    if (expected.empty()) continue;
    std::vector<int> ids(static_cast<size_t>(std::max(dimensions, 0)));
    if (nc_inq_vardimid(nc, v, ids.data()) != NC_NOERR) continue;
    const auto length_of_dimension = [&](int id) {
      size_t length = 0;
      return nc_inq_dimlen(nc, id, &length) == NC_NOERR ? length : SIZE_MAX;
    };
    const auto length_named = [&](const std::string& dimension) {
      int id = -1;
      return nc_inq_dimid(nc, dimension.c_str(), &id) == NC_NOERR ? length_of_dimension(id) : SIZE_MAX - 1;
    };
    bool same = ids.size() == expected.size();
    for (size_t k = 0; same && k < ids.size(); ++k)
      same = length_of_dimension(ids[k]) == length_named(expected[k]);
    if (!same) {
      std::string want;
      for (const std::string& e : expected) want += (want.empty() ? "" : ", ") + e;
      throw FormatError(path + ": its variable '" + name + "' is not shaped as Exodus's (" + want + ")");
    }
  }
  static const std::set<std::string> kScalars = {"api_version",
                                                 "api version",
                                                 "version",
                                                 "floating_point_word_size",
                                                 "floating point word size",
                                                 "file_size",
                                                 "int64_status",
                                                 "maximum_name_length",
                                                 "nemesis_file_version"};
  for (int v = NC_GLOBAL; v < variables; ++v) {
    int attributes = 0;
    if (nc_inq_varnatts(nc, v, &attributes) != NC_NOERR) continue;
    for (int a = 0; a < attributes; ++a) {
      char name[NC_MAX_NAME + 1] = {};
      nc_type type = 0;
      size_t length = 0;
      if (nc_inq_attname(nc, v, a, name) != NC_NOERR || nc_inq_att(nc, v, name, &type, &length) != NC_NOERR)
        continue;
      const std::string n = name;
      // (33 bytes fill the buffer: only with their terminator, which 6.02's
      // strcpy() of it then finds.)
      if ((n == "elem_type" || n == "name") && type == NC_CHAR && length == MAX_STR_LENGTH + 1) {
        char text[MAX_STR_LENGTH + 1] = {};
        if (nc_get_att_text(nc, v, name, text) == NC_NOERR && text[MAX_STR_LENGTH] != '\0')
          throw FormatError(path + ": its attribute '" + n + "' fills 33 bytes without its end");
      }
      if (((n == "elem_type" || n == "name") && length > MAX_STR_LENGTH + 1) ||
          (v == NC_GLOBAL && kScalars.count(n) && length > 1))
        throw FormatError(
            path + ": its attribute '" + n + "' holds " + std::to_string(length) +
            " values, more than an Exodus file's (" +
            (length > 1 && kScalars.count(n) ? std::string("1") : std::to_string(MAX_STR_LENGTH + 1)) + ")");
    }
  }
}

}  // namespace

File File::open(const std::string& path) {
  check_netcdf_header(path);
  check_variables_and_attributes(path);
  // (Quiet: errors reach the user through ours, naming the file.)
  ex_opts(EX_DEFAULT);
  int cpu_ws = 8, io_ws = 0;
  float version = 0;
  const int id = ex_open(path.c_str(), EX_READ, &cpu_ws, &io_ws, &version);
  if (id < 0)
    throw FormatError(path + ": not an Exodus II file (netCDF cannot open it" +
                      (last_error().empty() ? std::string() : ": " + last_error()) + ")");
  File file(id, path, false, io_ws);
  file.check(ex_set_int64_status(id, EX_ALL_INT64_API), "its integer size");
  file.check(ex_set_max_name_length(id, kNameLength), "its names' length");
  return file;
}

File File::create(const std::string& path) {
  ex_opts(EX_DEFAULT);
  int cpu_ws = 8, io_ws = 8;
  const int id = ex_create(path.c_str(), EX_CLOBBER | EX_LARGE_MODEL, &cpu_ws, &io_ws);
  if (id < 0) throw std::runtime_error(path + ": libexodusii cannot create it: " + last_error());
  File file(id, path, true, io_ws);
  file.check(ex_set_int64_status(id, EX_ALL_INT64_API), "its integer size");
  // (Names as long as a stream's: 64 bytes, where Exodus's default is 32.)
  file.check(ex_set_option(id, EX_OPT_MAX_NAME_LENGTH, kWrittenNameLength), "its names' length");
  return file;
}

File::~File() {
  if (id_ >= 0) ex_close(id_);
}

void File::close() {
  const int id = id_;
  id_ = -1;
  check(ex_close(id), "closing it");
}

void File::check(int rc, const std::string& what) const {
  if (rc >= 0) return;
  const std::string message = path_ + ": " + what + ": " + (last_error().empty() ? "failed" : last_error());
  if (writing_) throw std::runtime_error(message);
  throw FormatError(message);
}

ElementType element_type(std::string_view name, int64_t nodes) {
  std::string n;
  for (char c : name)
    if (std::isalpha(static_cast<unsigned char>(c)))
      n += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const auto is = [&](std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* k) { return n == k; });
  };
  const auto with = [&](Shape shape, int corners, bool faces_are_sides = false) {
    return nodes >= corners ? ElementType{shape, corners, faces_are_sides} : ElementType{};
  };
  if (is({"TETRA", "TET"})) return with(Shape::kTetrahedron, 4);
  if (is({"PYRAMID", "PYRA"})) return with(Shape::kPyramid, 5);
  if (is({"WEDGE"})) return with(Shape::kWedge, 6);
  if (is({"HEX", "HEXAHEDRON"})) return with(Shape::kHexahedron, 8);
  if (is({"TRI", "TRIANGLE", "TRISHELL"})) return with(Shape::kTriangle, 3, true);
  // (A 4-node SHELL or QUAD in a 3D mesh; SHELL2 and SHELL3 are 2D shells' edges.)
  if (is({"SHELL"}) && nodes >= 4) return with(Shape::kQuadrilateral, 4, true);
  if (is({"QUAD", "QUADRILATERAL"})) return with(Shape::kQuadrilateral, 4);
  return {};
}

Side side_of(Shape shape, int64_t side) {
  // Exodus's tables, nodes 1-based there.
  using S = std::initializer_list<std::initializer_list<int>>;
  static const auto make = [](S sides) {
    std::vector<Side> out;
    for (const auto& s : sides) {
      Side x;
      for (int v : s) x.slots[static_cast<size_t>(x.count++)] = v - 1;
      out.push_back(x);
    }
    return out;
  };
  static const std::vector<Side> kTet = make({{1, 2, 4}, {2, 3, 4}, {1, 4, 3}, {1, 3, 2}});
  static const std::vector<Side> kPyramid = make({{1, 2, 5}, {2, 3, 5}, {3, 4, 5}, {4, 1, 5}, {1, 4, 3, 2}});
  static const std::vector<Side> kWedge =
      make({{1, 2, 5, 4}, {2, 3, 6, 5}, {1, 4, 6, 3}, {1, 3, 2}, {4, 5, 6}});
  static const std::vector<Side> kHex =
      make({{1, 2, 6, 5}, {2, 3, 7, 6}, {3, 4, 8, 7}, {1, 5, 8, 4}, {1, 4, 3, 2}, {5, 6, 7, 8}});
  // A shell's sides 1 and 2 are its two faces; the others its edges.
  static const std::vector<Side> kTriangle = make({{1, 2, 3}, {1, 3, 2}});
  static const std::vector<Side> kQuad = make({{1, 2, 3, 4}, {1, 4, 3, 2}});
  const std::vector<Side>* table = nullptr;
  switch (shape) {
    case Shape::kTetrahedron:
      table = &kTet;
      break;
    case Shape::kPyramid:
      table = &kPyramid;
      break;
    case Shape::kWedge:
      table = &kWedge;
      break;
    case Shape::kHexahedron:
      table = &kHex;
      break;
    case Shape::kTriangle:
      table = &kTriangle;
      break;
    case Shape::kQuadrilateral:
      table = &kQuad;
      break;
    case Shape::kOther:
      return {};
  }
  if (side < 1 || side > static_cast<int64_t>(table->size())) return {};
  return (*table)[static_cast<size_t>(side - 1)];
}

}  // namespace dtm::exodus
