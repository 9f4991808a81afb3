// The last check of the exact cell fill (exact_cell_coder_shared.h): no two
// cells of level 0 overlap, though they share no face. The fill's own checks
// (orientation, at most two cells a face, on opposite sides) make level 0 a
// pseudo-manifold; only this makes it a mesh, not a complex folded over
// itself.
//
// The Delaunay tetrahedralization both sides hold is the index: its cells
// tile the convex hull, where every cell lies. A fill cell's interior meets a
// set of Delaunay cells connected through their faces (the interior is
// convex, and a path in it can avoid the Delaunay edges), found by a walk
// from one of them. A fill cell may meet no kept Delaunay cell (those are
// level 0's other cells), and two fill cells overlap exactly when they meet
// one Delaunay cell's interior at one point, so only fill cells meeting a
// common Delaunay cell are compared.
//
// A mesher's non-Delaunay cells each meet a few Delaunay cells; the walks
// and the comparisons stop past budgets proportional to the fill's cells
// (exact_cell_coder_shared.h), so that a hostile section of long cells
// costs time linear in its cells, and the encoder refuses such an input
// with the same words.
#include <algorithm>
#include <atomic>
#include <string>
#include <vector>

#include "codec/sections/exact_cell_coder_shared.h"
#include "common/parallel_sort.h"

namespace dtm::exact_cells {
namespace {

std::array<GridPoint, 4> corners(std::span<const GridPoint> points, const MeshCell& c) {
  return {points[c[0]], points[c[1]], points[c[2]], points[c[3]]};
}

// The Delaunay cells one walk has tested: open addressing, emptied by the
// slots it used, so that a long walk costs no more than a short one a cell.
class Tested {
 public:
  // True when d was not in the set (and is now).
  bool insert(uint32_t d) {
    if (2 * (used_.size() + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t i = (d * 0x9E3779B1u) & mask;; i = (i + 1) & mask) {
      if (slots_[i] == d) return false;
      if (slots_[i] == kEmpty) {
        slots_[i] = d;
        used_.push_back(i);
        return true;
      }
    }
  }
  void clear() {
    for (size_t i : used_) slots_[i] = kEmpty;
    used_.clear();
  }

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;
  void grow() {
    std::vector<uint32_t> items;
    for (size_t i : used_) items.push_back(slots_[i]);
    slots_.assign(std::max<size_t>(256, 2 * slots_.size()), kEmpty);
    used_.clear();
    for (uint32_t d : items) insert(d);
  }
  std::vector<uint32_t> slots_;
  std::vector<size_t> used_;
};

// True when the face of m opposite its corner k is a face of c.
bool own_face(const MeshCell& c, const MeshCell& m, size_t k) {
  for (size_t i = 0; i < 4; ++i)
    if (i != k && std::find(c.begin(), c.end(), m[i]) == c.end()) return false;
  return true;
}

struct Met {
  uint32_t delaunay = 0;  // a Delaunay cell
  uint32_t fill = 0;      // a fill cell whose interior meets it
};

}  // namespace

Status check_cells_apart(const TetMesh& dt, std::span<const GridPoint> points, std::span<const uint8_t> kept,
                         const ExactFill& fill, const Csr& incident) {
  const size_t n = fill.cells.size();
  if (n == 0) return Status::Ok();
  // Where each walk starts: the Delaunay cell across a kept cell's face
  // from it, on the fill cell's side of their common face.
  std::vector<int32_t> start(n, -1);
  for (const ExactFill::Link& l : fill.links) {
    const size_t j = static_cast<size_t>(l.other) - dt.cells.size();
    if (j < n && start[j] < 0) start[j] = dt.neighbors[l.cell][l.corner];
  }

  // Every fill cell's walk: the Delaunay cells its interior meets.
  const uint64_t most_meetings = kMeetingsPerCell * n + 4096, most_tests = kTestsPerCell * n + 65536;
  std::atomic<uint64_t> meetings = 0, tests = 0;
  constexpr size_t kBlock = 2048;
  const size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::string> problems(blocks);
  std::vector<std::vector<Met>> met(blocks);
  parallel_for(
      blocks,
      [&](size_t b) {
        std::vector<uint32_t> found;
        Tested tested;
        const auto refuse = [&](const char* why) { problems[b] = why; };
        for (size_t j = b * kBlock; j < std::min(n, b * kBlock + kBlock); ++j) {
          const std::array<GridPoint, 4> cell = corners(points, fill.cells[j]);
          const uint64_t tests_before = tests.load(std::memory_order_relaxed);
          uint64_t cell_tests = 0;
          const auto meets = [&](uint32_t d) {
            ++cell_tests;
            return interiors_meet(cell, corners(points, dt.cells[d]));
          };
          const char* too_long = "its cells cross too many Delaunay cells";
          found.clear();
          tested.clear();
          if (start[j] >= 0) {
            found.push_back(static_cast<uint32_t>(start[j]));
          } else {
            // Near its corner, the cell lies in that corner's Delaunay cells.
            const MeshCell& c = fill.cells[j];
            const uint32_t v = *std::min_element(c.begin(), c.end(), [&](uint32_t x, uint32_t y) {
              return incident.row(x).size() < incident.row(y).size();
            });
            for (uint32_t d : incident.row(v))
              if (meets(d)) {
                found.push_back(d);
                break;
              }
            if (found.empty()) return refuse("a cell outside the Delaunay cells");
          }
          tested.insert(found[0]);
          for (size_t i = 0; i < found.size(); ++i) {
            if (kept[found[i]]) return refuse("a cell overlaps a kept Delaunay cell");
            met[b].push_back({found[i], static_cast<uint32_t>(j)});
            const MeshCell& m = dt.cells[found[i]];
            for (size_t k = 0; k < 4; ++k) {
              const int32_t d = dt.neighbors[found[i]][k];
              // Across a face of the fill cell itself lies what the fill
              // cell does not reach.
              if (d < 0 || own_face(fill.cells[j], m, k) || !tested.insert(static_cast<uint32_t>(d)))
                continue;
              if (meets(static_cast<uint32_t>(d))) found.push_back(static_cast<uint32_t>(d));
            }
            if (found.size() > kMaxMeetings) return refuse("a cell crosses too many Delaunay cells");
            if (tests_before + cell_tests > most_tests) return refuse(too_long);
          }
          tests.fetch_add(cell_tests, std::memory_order_relaxed);
          if (meetings.fetch_add(found.size(), std::memory_order_relaxed) + found.size() > most_meetings)
            return refuse(too_long);
        }
      },
      2);
  for (const std::string& p : problems)
    if (!p.empty()) return corrupt(p);

  // Fill cells by the Delaunay cell they meet; each group's pairs apart.
  std::vector<Met> pairs;
  pairs.reserve(meetings.load());
  for (auto& m : met) pairs.insert(pairs.end(), m.begin(), m.end()), m = {};
  parallel_sort(pairs.begin(), pairs.end(), [](const Met& x, const Met& y) {
    return x.delaunay != y.delaunay ? x.delaunay < y.delaunay : x.fill < y.fill;
  });
  struct Group {
    size_t begin, end;
  };
  std::vector<Group> groups;  // of two or more
  uint64_t comparisons = 0;
  for (size_t i = 0, j = 0; i < pairs.size(); i = j) {
    while (j < pairs.size() && pairs[j].delaunay == pairs[i].delaunay) ++j;
    if (j - i < 2) continue;
    groups.push_back({i, j});
    comparisons += (j - i) * (j - i - 1) / 2;
  }
  if (comparisons > kComparisonsPerMeeting * pairs.size() + 65536)
    return corrupt("too many of its cells meet one Delaunay cell");
  std::vector<uint8_t> overlap(groups.size(), 0);
  parallel_ranges(groups.size(), 1024, [&](size_t first, size_t last) {
    for (size_t g = first; g < last; ++g)
      for (size_t x = groups[g].begin; x < groups[g].end && !overlap[g]; ++x)
        for (size_t y = x + 1; y < groups[g].end && !overlap[g]; ++y)
          overlap[g] = interiors_meet(corners(points, fill.cells[pairs[x].fill]),
                                      corners(points, fill.cells[pairs[y].fill]));
  });
  if (std::find(overlap.begin(), overlap.end(), 1) != overlap.end()) return corrupt("two cells overlap");
  return Status::Ok();
}

}  // namespace dtm::exact_cells
