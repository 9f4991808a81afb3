#include "abaqus_syntax.h"

#include <algorithm>
#include <cctype>

#include "text_cursor.h"  // parse_whole

namespace dtm::abaqus {

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trimmed(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

namespace {

std::string_view unquoted(std::string_view s) {
  return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}

// Splits at the commas outside double quotes.
std::vector<std::string_view> pieces(std::string_view line) {
  std::vector<std::string_view> out;
  bool quoted = false;
  size_t start = 0;
  for (size_t at = 0; at <= line.size(); ++at) {
    if (at < line.size() && line[at] == '"') quoted = !quoted;
    if (at == line.size() || (line[at] == ',' && !quoted)) {
      out.push_back(trimmed(line.substr(start, at - start)));
      start = at + 1;
    }
  }
  return out;
}

}  // namespace

std::vector<std::string_view> entries(std::string_view line) {
  std::vector<std::string_view> out = pieces(line);
  if (!out.empty() && out.back().empty()) out.pop_back();
  for (std::string_view& e : out) e = unquoted(e);
  return out;
}

bool Keyword::has(std::string_view p) const {
  return std::any_of(parameters.begin(), parameters.end(), [&](const auto& q) { return q.first == p; });
}

std::string Keyword::value(std::string_view p) const {
  for (const auto& [n, v] : parameters)
    if (n == p) return v;
  return {};
}

Keyword keyword_of(std::string_view line) {
  const auto name_of = [](std::string_view s) {
    std::string n = upper(s);
    std::erase_if(n, [](char c) { return c == ' ' || c == '\t'; });
    return n;
  };
  const std::vector<std::string_view> p = pieces(line.substr(1));  // (past the '*')
  Keyword k;
  k.name = name_of(p.front());
  k.written = upper(p.front());
  for (size_t i = 1; i < p.size(); ++i) {
    if (p[i].empty()) continue;
    const size_t eq = p[i].find('=');
    std::string name = name_of(p[i].substr(0, eq));
    std::string value =
        eq == std::string_view::npos ? "" : std::string(unquoted(trimmed(p[i].substr(eq + 1))));
    k.parameters.emplace_back(std::move(name), std::move(value));
  }
  return k;
}

ElementType element_type(const std::string& type) {
  const auto digits_after = [&](std::string_view prefix) -> int {
    if (type.rfind(prefix, 0) != 0) return -1;
    size_t end = prefix.size();
    while (end < type.size() && std::isdigit(static_cast<unsigned char>(type[end]))) ++end;
    int n = -1;
    if (end == prefix.size() ||
        !parse_whole(std::string_view(type).substr(prefix.size(), end - prefix.size()), n))
      return -1;
    return n;
  };
  for (const char* prefix : {"DC3D", "C3D"}) {
    switch (digits_after(prefix)) {
      case 4:
        return {Shape::kTetrahedron, 4, 4};
      case 10:
        return {Shape::kTetrahedron, 10, 4};
      case 5:
        return {Shape::kPyramid, 5, 5};
      case 6:
        return {Shape::kPrism, 6, 6};
      case 15:
        return {Shape::kPrism, 15, 6};
      case 8:
        return {Shape::kHexahedron, 8, 8};
      case 20:
        return {Shape::kHexahedron, 20, 8};
      case 27:
        return {Shape::kHexahedron, 27, 8};
      default:
        break;
    }
  }
  for (const char* prefix : {"SFM3D", "M3D", "R3D", "STRI", "CPS", "CPE", "DS", "S"}) {
    int n = digits_after(prefix);
    if (n == 65) n = 6;  // STRI65
    if (n == 3 || n == 6) return {Shape::kTriangle, n, 3};
    if (n == 4 || n == 8 || n == 9) return {Shape::kQuadrilateral, n, 4};
    if (n >= 0) break;
  }
  return {};
}

FaceSlots face_slots(Shape shape, int face) {
  using Table = std::array<FaceSlots, 6>;
  static const Table tetrahedron = {
      {{3, {0, 1, 2}}, {3, {0, 3, 1}}, {3, {1, 3, 2}}, {3, {2, 3, 0}}, {0, {}}, {0, {}}}};
  static const Table pyramid = {
      {{4, {0, 1, 2, 3}}, {3, {0, 4, 1}}, {3, {1, 4, 2}}, {3, {2, 4, 3}}, {3, {3, 4, 0}}, {0, {}}}};
  static const Table prism = {
      {{3, {0, 1, 2}}, {3, {3, 5, 4}}, {4, {0, 3, 4, 1}}, {4, {1, 4, 5, 2}}, {4, {2, 5, 3, 0}}, {0, {}}}};
  static const Table hexahedron = {{{4, {0, 1, 2, 3}},
                                    {4, {4, 7, 6, 5}},
                                    {4, {0, 4, 5, 1}},
                                    {4, {1, 5, 6, 2}},
                                    {4, {2, 6, 7, 3}},
                                    {4, {3, 7, 4, 0}}}};
  if (face < 0 || face > 5) return {};
  const auto f = static_cast<size_t>(face);
  switch (shape) {
    case Shape::kTetrahedron:
      return tetrahedron[f];
    case Shape::kPyramid:
      return pyramid[f];
    case Shape::kPrism:
      return prism[f];
    case Shape::kHexahedron:
      return hexahedron[f];
    default:
      return {};
  }
}

}  // namespace dtm::abaqus
