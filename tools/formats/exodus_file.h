// What the Exodus II reader and writer share: an open file that closes
// itself, errors that name the file, and the element types' tables.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dtm::exodus {

// An Exodus file open through libexodusii, 64-bit integers throughout and
// names up to kNameLength; closed when it goes out of scope.
class File {
 public:
  // Throws FormatError naming `path` if it is not an Exodus file.
  static File open(const std::string& path);
  // Creates (replaces) `path`: netCDF classic with 64-bit offsets, doubles.
  // Throws std::runtime_error.
  static File create(const std::string& path);
  File(File&& other) noexcept : id_(other.id_), path_(std::move(other.path_)), writing_(other.writing_) {
    other.id_ = -1;
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  File& operator=(File&&) = delete;
  ~File();

  int id() const { return id_; }
  const std::string& path() const { return path_; }
  // The file's word size for real numbers (4: floats, 8: doubles).
  int io_word_size() const { return io_ws_; }
  // Throws, naming the file, `what` and libexodusii's message, if rc < 0:
  // FormatError when reading, std::runtime_error when writing.
  void check(int rc, const std::string& what) const;
  // The same for a warning too (rc > 0: libexodusii did not find what was
  // asked, and left the buffer as it was).
  void require(int rc, const std::string& what) const { check(rc > 0 ? -rc : rc, what); }
  // Closes the file now (the writer's data reaches the disk); throws as check().
  void close();

 private:
  File(int id, std::string path, bool writing, int io_ws)
      : id_(id), path_(std::move(path)), writing_(writing), io_ws_(io_ws) {}
  int id_ = -1;
  std::string path_;
  bool writing_ = false;
  int io_ws_ = 8;
};

inline constexpr int kNameLength = 255;        // read
inline constexpr int kWrittenNameLength = 64;  // written

// The shapes the codec reads.
enum class Shape { kTetrahedron, kPyramid, kWedge, kHexahedron, kTriangle, kQuadrilateral, kOther };

// An element block's shape from its type name (ignoring case: TETRA, TET4,
// HEX8, WEDGE15, PYRAMID5, TRISHELL3, SHELL4, QUAD4, ...) and nodes per
// element, and how many of those nodes are its corners; kOther for bars,
// beams, spheres, polyhedra and what is not known.
struct ElementType {
  Shape shape = Shape::kOther;
  int corners = 0;
  // A triangle or a SHELL's sides 1 and 2 are its faces (side_of()); a
  // QUAD's sides are its edges, as libexodusii's tables have them.
  bool faces_are_sides = false;
};
ElementType element_type(std::string_view name, int64_t nodes_per_element);

// The corners (0-based slots of the element's nodes) of side `side`
// (1-based, as a side set numbers it), turned outward, as Exodus lists them
// (SEACAS's element types page): 3 or 4 of them; count 0 where the side is
// not a face (a shell's edges, a number out of range).
struct Side {
  std::array<int, 4> slots{};
  int count = 0;
};
Side side_of(Shape shape, int64_t side);

// The edge nodes of a 10-node tetrahedron in Exodus's order (corners 0-3,
// then the edges 0-1, 1-2, 0-2, 0-3, 1-3, 2-3, VTK's order too): for each
// edge of second_order.h's kTetEdges, the slot of its node.
inline constexpr std::array<int, 6> kTet10EdgeSlots = {4, 6, 7, 5, 8, 9};

}  // namespace dtm::exodus
