#include "point_set_text.h"

#include <charconv>
#include <fstream>
#include <string_view>

#include "format_error.h"
#include "text_cursor.h"

namespace dtm {
namespace {

// A line's blank-separated words, up to a comment ('#' to the line's end,
// which OFF allows anywhere and CGAL's readers pass over).
std::vector<std::string_view> words_of(std::string_view line) {
  line = line.substr(0, line.find('#'));
  std::vector<std::string_view> out;
  size_t at = 0;
  while (true) {
    at = line.find_first_not_of(" \t\r\f\v", at);
    if (at == std::string_view::npos) return out;
    const size_t end = std::min(line.size(), line.find_first_of(" \t\r\f\v", at));
    out.push_back(line.substr(at, end - at));
    at = end;
  }
}

bool is_number(std::string_view w) {
  if (!w.empty() && w.front() == '+') w.remove_prefix(1);  // (from_chars takes no '+')
  double value = 0;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), value);
  return !w.empty() && end == w.data() + w.size() && ec != std::errc::invalid_argument;
}

class Lines {
 public:
  explicit Lines(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    skip_byte_order_mark(in_);
  }
  // The next line (false at the end), its words in `words`.
  bool next(std::vector<std::string_view>& words) {
    if (!std::getline(in_, line_)) return false;
    ++number_;
    words = words_of(line_);
    return true;
  }
  uint64_t number() const { return number_; }
  [[noreturn]] void fail(const std::string& problem) const {
    throw FormatError(path_ + ":" + std::to_string(number_) + ": " + problem);
  }
  // Every word a number, or the first that is not named.
  void numbers(const std::vector<std::string_view>& words, size_t from) const {
    for (size_t i = from; i < words.size(); ++i)
      if (!is_number(words[i]))
        fail("expected a number, found '" + std::string(words[i].substr(0, 40)) + "'");
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::string line_;
  uint64_t number_ = 0;
};

void check_xyz(const std::string& path, size_t points_read) {
  Lines lines(path);
  std::vector<std::string_view> w;
  size_t points = 0;
  while (lines.next(w)) {
    if (w.empty()) continue;
    lines.numbers(w, 0);
    if (lines.number() == 1 && w.size() == 1) continue;  // the point count, which the first line may give
    if (w.size() != 3 && w.size() != 6)
      lines.fail("expected 3 numbers (x y z) or 6 (x y z nx ny nz), found " + std::to_string(w.size()) +
                 " (an XYZ names no column: save colours or scalars as PLY, whose header names them)");
    ++points;
  }
  if (points != points_read)
    throw FormatError(path + ": " + std::to_string(points) + " point lines, of which CGAL's reader took " +
                      std::to_string(points_read));
}

void check_obj(const std::string& path, size_t points_read, std::vector<std::string>& left_out) {
  Lines lines(path);
  std::vector<std::string_view> w;
  size_t points = 0, coloured = 0;
  while (lines.next(w)) {
    if (w.empty() || w.front() != "v") continue;
    lines.numbers(w, 1);
    const size_t n = w.size() - 1;
    if (n == 6 || n == 7)
      ++coloured;  // x y z r g b (MeshLab's), or x y z w r g b
    else if (n != 3 && n != 4)
      lines.fail("a vertex is 'v x y z' (or 'v x y z w', or with 'r g b' after), found " + std::to_string(n) +
                 " numbers");
    ++points;
  }
  if (points != points_read)
    throw FormatError(path + ": " + std::to_string(points) + " 'v' lines, of which CGAL's reader took " +
                      std::to_string(points_read));
  if (coloured > 0) left_out.push_back("the colours of " + std::to_string(coloured) + " vertices (r g b)");
}

// A plain OFF's (header "OFF" alone on its line): its vertex lines, x y z
// each, as many as the header announces and no more where it announces no
// faces (with faces, the lines after the vertices are theirs, not read).
void check_off(const std::string& path, size_t points_read) {
  Lines lines(path);
  std::vector<std::string_view> w;
  const auto next_content = [&] {
    while (lines.next(w))
      if (!w.empty()) return true;
    return false;
  };
  if (!next_content() || w.size() != 1 || w.front() != "OFF") return;  // another variant: CGAL's to judge
  if (!next_content() || w.size() < 2) return;
  lines.numbers(w, 0);
  uint64_t vertices = 0, faces = 0;
  std::from_chars(w[0].data(), w[0].data() + w[0].size(), vertices);
  std::from_chars(w[1].data(), w[1].data() + w[1].size(), faces);
  for (uint64_t i = 0; i < vertices && i < points_read; ++i) {
    if (!next_content()) return;  // (the count's check says it)
    lines.numbers(w, 0);
    if (w.size() != 3) lines.fail("an OFF vertex is 'x y z', found " + std::to_string(w.size()) + " numbers");
  }
  if (faces == 0 && vertices == points_read && next_content())
    lines.fail("more lines than the header's " + std::to_string(vertices) + " vertices and no faces");
}

void check_ply(const std::string& path, const PlyVertexLines& ply) {
  Lines lines(path);
  std::vector<std::string_view> w;
  while (lines.next(w))
    if (!w.empty() && w.front() == "end_header") break;
  for (uint64_t i = 0; i < ply.count; ++i) {
    do {
      if (!lines.next(w)) return;  // (CGAL's reader said it)
    } while (w.empty());           // (blank lines between the vertices, which CGAL passes over)
    lines.numbers(w, 0);
    if (w.size() != ply.properties)
      lines.fail("a vertex has " + std::to_string(ply.properties) + " properties, this line " +
                 std::to_string(w.size()) + " numbers");
  }
  while (ply.only_element && lines.next(w))
    if (!w.empty()) lines.fail("more lines than the header's " + std::to_string(ply.count) + " vertices");
}

}  // namespace

void check_point_set_text(const std::string& path, PointSetFormat format, size_t points_read,
                          const PlyVertexLines* ply, std::vector<std::string>& left_out) {
  switch (format) {
    case PointSetFormat::kXyz:
      return check_xyz(path, points_read);
    case PointSetFormat::kObj:
      return check_obj(path, points_read, left_out);
    case PointSetFormat::kOff:
      return check_off(path, points_read);
    case PointSetFormat::kPly:
      if (ply) check_ply(path, *ply);
      return;
  }
}

}  // namespace dtm
