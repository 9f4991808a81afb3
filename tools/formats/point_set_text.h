// The text of an ASCII point set read line by line, after CGAL's reader
// took its points: CGAL's istream parsing takes "0.5L7" as 0.5, passes over
// a line's extra numbers and stops quietly where a count ends, so wrong
// points or dropped values would go unsaid. Here each vertex line must hold
// whole numbers, as many as the format gives a vertex, and the lines as
// many as CGAL read; what a vertex line holds beyond its coordinates (an
// OBJ's colours) is named.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "point_sets.h"

namespace dtm {

// An ASCII PLY's vertex element, where it comes first and has no lists
// (the only layout checked line by line): its count and properties.
struct PlyVertexLines {
  uint64_t count = 0;
  size_t properties = 0;
  bool only_element = false;  // no element after it
};

// Throws FormatError "path:line: ..." where a line breaks the format.
void check_point_set_text(const std::string& path, PointSetFormat format, size_t points_read,
                          const PlyVertexLines* ply, std::vector<std::string>& left_out);

}  // namespace dtm
