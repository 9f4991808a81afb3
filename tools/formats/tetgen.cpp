#include "tetgen.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

namespace dtm {
namespace {

// Reads the non-comment, non-blank lines of a file, remembering line numbers.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw FormatError(path + ": cannot open file");
  }
  // The next meaningful line split into tokens; false at end of file.
  bool next(std::vector<std::string_view>& tokens) {
    while (std::getline(in_, line_)) {
      ++number_;
      if (auto hash = line_.find('#'); hash != std::string::npos) line_.resize(hash);
      tokens.clear();
      std::string_view rest(line_);
      while (true) {
        const size_t b = rest.find_first_not_of(" \t\r,");
        if (b == std::string_view::npos) break;
        rest.remove_prefix(b);
        const size_t e = rest.find_first_of(" \t\r,");
        tokens.push_back(rest.substr(0, e));
        if (e == std::string_view::npos) break;
        rest.remove_prefix(e);
      }
      if (!tokens.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& problem) const {
    throw FormatError(path_ + ":" + std::to_string(number_) + ": " + problem);
  }
  template <class T>
  T parse(std::string_view token, const char* what) const {
    T value{};
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size())
      fail(std::string("expected ") + what + ", found '" + std::string(token) + "'");
    return value;
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::string line_;
  size_t number_ = 0;
};

}  // namespace

NodeFile read_tetgen_node(const std::string& path) {
  LineReader r(path);
  std::vector<std::string_view> tok;
  if (!r.next(tok)) throw FormatError(path + ": empty file, expected a .node header");
  if (tok.size() < 2 || tok.size() > 4)
    r.fail("expected a header '<points> <dimension> [<attributes> <markers>]'");
  const auto count = r.parse<uint64_t>(tok[0], "a point count");
  const auto dim = r.parse<int>(tok[1], "a dimension");
  const int attributes = tok.size() > 2 ? r.parse<int>(tok[2], "an attribute count") : 0;
  const int has_marker = tok.size() > 3 ? r.parse<int>(tok[3], "0 or 1 boundary markers") : 0;
  if (dim != 3) r.fail("dimension must be 3, got " + std::to_string(dim));
  if (attributes < 0 || has_marker < 0 || has_marker > 1) r.fail("bad attribute or marker count");
  if (count > (uint64_t{1} << 31)) r.fail("point count " + std::to_string(count) + " is too large");

  NodeFile out;
  out.points.reserve(std::min<uint64_t>(count, 1 << 20));  // grow with the data, not the claim
  const size_t expected = 4 + attributes + has_marker;
  int64_t first_index = 0;
  for (uint64_t i = 0; i < count; ++i) {
    if (!r.next(tok))
      throw FormatError(path + ": file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                        " points");
    if (tok.size() != expected)
      r.fail("expected " + std::to_string(expected) + " fields, found " + std::to_string(tok.size()));
    const auto index = r.parse<int64_t>(tok[0], "a point index");
    if (i == 0) {
      if (index != 0 && index != 1) r.fail("the first point index must be 0 or 1");
      first_index = index;
    } else if (index != first_index + static_cast<int64_t>(i)) {
      r.fail("point index " + std::to_string(index) + " out of sequence");
    }
    InputPoint p{r.parse<double>(tok[1], "a coordinate"), r.parse<double>(tok[2], "a coordinate"),
                 r.parse<double>(tok[3], "a coordinate")};
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) r.fail("coordinate is not finite");
    out.points.push_back(p);
    for (int a = 0; a < attributes; ++a)
      out.attributes.push_back(r.parse<double>(tok[4 + a], "an attribute"));
    if (has_marker) out.markers.push_back(r.parse<int>(tok[expected - 1], "a boundary marker"));
  }
  out.index_base = static_cast<int>(first_index);
  out.attribute_count = attributes;
  if (r.next(tok)) r.fail("unexpected data after the " + std::to_string(count) + " points");
  return out;
}

int tetgen_ele_attributes(const std::string& path) {
  LineReader r(path);
  std::vector<std::string_view> tok;
  if (!r.next(tok) || tok.size() < 3) return 0;
  return std::max(0, r.parse<int>(tok[2], "an attribute count"));
}

std::vector<std::array<uint32_t, 4>> read_tetgen_ele(
    const std::string& path, size_t num_points, int index_base,
    const std::function<bool(const std::array<uint32_t, 4>&)>& keep, std::vector<int32_t>* regions) {
  LineReader r(path);
  std::vector<std::string_view> tok;
  if (!r.next(tok)) throw FormatError(path + ": empty file, expected an .ele header");
  if (tok.size() < 2 || tok.size() > 3)
    r.fail("expected a header '<tetrahedra> <nodes per tet> [<attributes>]'");
  const auto count = r.parse<uint64_t>(tok[0], "a tetrahedron count");
  const auto per = r.parse<int>(tok[1], "nodes per tetrahedron");
  const int attributes = tok.size() > 2 ? r.parse<int>(tok[2], "an attribute count") : 0;
  if (per != 4) r.fail("only linear tetrahedra (4 nodes) are supported, got " + std::to_string(per));
  if (attributes < 0) r.fail("bad attribute count");
  using Tet = std::array<uint32_t, 4>;
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
  constexpr size_t kPiece = size_t{1} << 17;  // tetrahedra: 2 MiB
  std::vector<std::vector<Tet>> pieces;
  for (uint64_t i = 0; i < count; ++i) {
    if (!r.next(tok))
      throw FormatError(path + ": file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                        " tetrahedra");
    if (tok.size() != 5 + static_cast<size_t>(attributes))
      r.fail("expected " + std::to_string(5 + attributes) + " fields");
    Tet t;
    for (int k = 0; k < 4; ++k) {
      const auto v = r.parse<int64_t>(tok[1 + k], "a vertex index") - index_base;
      if (v < 0 || static_cast<uint64_t>(v) >= num_points)
        r.fail("vertex index " + std::string(tok[1 + k]) + " out of range");
      t[k] = static_cast<uint32_t>(v);
    }
    if (regions && attributes > 0 && !keep) {
      const auto a = r.parse<double>(tok[5], "a region attribute");
      if (a != std::floor(a) || a < INT32_MIN || a > INT32_MAX)
        r.fail("a region attribute that is not a 32-bit integer: " + std::string(tok[5]));
      regions->push_back(static_cast<int32_t>(a));
    }
    if (!keep) {
      out.push_back(t);
    } else if (keep(t)) {
      if (pieces.empty() || pieces.back().size() == kPiece) pieces.emplace_back().reserve(kPiece);
      pieces.back().push_back(t);
    }
  }
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

}  // namespace dtm
