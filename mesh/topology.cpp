#include "mesh/topology.h"

#include <algorithm>
#include <tuple>

#include "common/atomic_counts.h"
#include "common/first_touch.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "common/threads.h"
#include "mesh/geometry.h"

namespace dtm {

Csr vertex_cells(std::span<const std::array<uint32_t, 4>> cells, size_t num_vertices) {
  // Each thread makes both passes over every cell for the rows of its own
  // range of vertices, so that every row lists its cells ascending, as one
  // pass in cell order would, with no atomics and no sort. A canonical mesh
  // lists its cells by their least corner, whose ids follow the points'
  // order: each thread's corners come in long runs and the test is nearly
  // always predicted. (Atomic counts and a sort of each row, before
  // 2026-12-03, were slower on 2 threads than one pass on one: 0.44 s
  // against 0.27 s at bunny_1m's level 0.)
  Csr out;
  out.offsets.assign(num_vertices + 1, 0);
  const auto n = static_cast<uint32_t>(num_vertices);
  const auto range_of = [n](size_t part, size_t parts) {
    return std::pair<uint32_t, uint32_t>(static_cast<uint32_t>(uint64_t{n} * part / parts),
                                         static_cast<uint32_t>(uint64_t{n} * (part + 1) / parts));
  };
  // A small mesh in one pass: starting threads would cost more.
  const auto each_part = [&](const auto& pass) {
    if (cells.size() < (size_t{1} << 15))
      pass(size_t{0}, size_t{1});
    else
      on_every_thread(pass);
  };
  each_part([&](size_t part, size_t parts) {
    const auto [lo, hi] = range_of(part, parts);
    for (const auto& cell : cells)
      for (uint32_t v : cell)
        if (v - lo < hi - lo) ++out.offsets[v + 1];
  });
  for (size_t v = 0; v < num_vertices; ++v) out.offsets[v + 1] += out.offsets[v];
  resize_on_every_core(out.items, out.offsets.back());
  std::vector<uint32_t> cursor(out.offsets.begin(), out.offsets.end() - 1);
  each_part([&](size_t part, size_t parts) {
    const auto [lo, hi] = range_of(part, parts);
    for (uint32_t c = 0; c < cells.size(); ++c)
      for (uint32_t v : cells[c])
        if (v - lo < hi - lo) out.items[cursor[v]++] = c;
  });
  return out;
}

Csr vertex_neighbors(std::span<const std::array<uint32_t, 4>> cells, const Csr& cells_of_vertex) {
  // The neighbours of v are the other corners of its cells; a stamp per
  // vertex (the last v that listed it) drops repeats without a hash or a
  // sort of the ~70 corners each vertex sees. Blocks of vertices on every
  // core, each thread with its stamps, joined in vertex order.
  const size_t n = cells_of_vertex.rows();
  constexpr size_t kBlock = 4096;
  const size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<uint32_t>> items(blocks), counts(blocks);
  parallel_for(
      blocks,
      [&](size_t block) {
        thread_local std::vector<uint32_t> stamp;
        if (stamp.size() < n) stamp.assign(n, UINT32_MAX);
        auto& out = items[block];
        for (uint32_t v = static_cast<uint32_t>(block * kBlock); v < std::min(n, block * kBlock + kBlock);
             ++v) {
          const size_t first = out.size();
          for (uint32_t c : cells_of_vertex.row(v))
            for (uint32_t u : cells[c])
              if (u != v && stamp[u] != v) {
                stamp[u] = v;
                out.push_back(u);
              }
          std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
          counts[block].push_back(static_cast<uint32_t>(out.size() - first));
        }
        // A later call with another mesh of as many vertices must not see
        // these stamps as its own.
        for (uint32_t u : out) stamp[u] = UINT32_MAX;
      },
      2);
  // Joined on every core: each block's rows go where the blocks before it end.
  std::vector<size_t> block_start(blocks + 1, 0);
  for (size_t b = 0; b < blocks; ++b) block_start[b + 1] = block_start[b] + items[b].size();
  Csr out;
  resize_on_every_core(out.offsets, n + 1);
  out.offsets[0] = 0;
  resize_on_every_core(out.items, block_start[blocks]);
  parallel_for(
      blocks,
      [&](size_t b) {
        auto total = static_cast<uint32_t>(block_start[b]);
        size_t v = b * kBlock;
        for (uint32_t k : counts[b]) out.offsets[++v] = total += k;
        std::copy(items[b].begin(), items[b].end(),
                  out.items.begin() + static_cast<std::ptrdiff_t>(block_start[b]));
        release(items[b]);
      },
      2);
  return out;
}

std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh, std::span<const uint8_t> in_mesh) {
  std::vector<BoundaryFace> out;
  for (uint32_t c = 0; c < mesh.cells.size(); ++c) {
    if (!in_mesh[c]) continue;
    for (uint8_t i = 0; i < 4; ++i) {
      const int32_t n = mesh.neighbors[c][i];
      if (n < 0 || !in_mesh[n]) out.push_back({c, i});
    }
  }
  return out;
}

std::vector<uint8_t> boundary_vertices(const TetMesh& mesh, size_t num_vertices,
                                       std::span<const uint8_t> in_mesh) {
  std::vector<uint8_t> out(num_vertices, 0), touched(num_vertices, 0);
  for (size_t c = 0; c < mesh.cells.size(); ++c)
    if (in_mesh[c])
      for (uint32_t v : mesh.cells[c]) touched[v] = 1;
  for (const BoundaryFace& f : boundary_faces(mesh, in_mesh))
    for (int i = 0; i < 4; ++i)
      if (i != f.opposite) out[mesh.cells[f.cell][i]] = 1;
  for (size_t v = 0; v < num_vertices; ++v)
    if (!touched[v]) out[v] = 1;
  return out;
}

std::array<uint32_t, 3> outward_triangle(const TetMesh& mesh, std::span<const GridPoint> points,
                                         const BoundaryFace& f) {
  const auto& c = mesh.cells[f.cell];
  std::array<uint32_t, 3> t;
  int k = 0;
  for (int i = 0; i < 4; ++i)
    if (i != f.opposite) t[k++] = c[i];
  const Vec3 a = to_vec(points[t[0]]), b = to_vec(points[t[1]]), d = to_vec(points[t[2]]);
  const Vec3 normal = cross(b - a, d - a);
  if (dot(normal, to_vec(points[c[f.opposite]]) - a) > 0) std::swap(t[1], t[2]);
  return t;
}

namespace {
std::array<uint32_t, 4> sorted4(std::array<uint32_t, 4> c) {
  if (c[0] > c[1]) std::swap(c[0], c[1]);
  if (c[2] > c[3]) std::swap(c[2], c[3]);
  if (c[0] > c[2]) std::swap(c[0], c[2]);
  if (c[1] > c[3]) std::swap(c[1], c[3]);
  if (c[1] > c[2]) std::swap(c[1], c[2]);
  return c;
}
}  // namespace

namespace {

// The largest vertex id of any cell (0 for none), on every core.
uint32_t largest_vertex(std::span<const std::array<uint32_t, 4>> cells) {
  constexpr size_t kRange = size_t{1} << 16;
  std::vector<uint32_t> range_top((cells.size() + kRange - 1) / kRange, 0);
  parallel_ranges(cells.size(), kRange, [&](size_t first, size_t last) {
    uint32_t top = 0;
    for (size_t c = first; c < last; ++c)
      top = std::max({top, cells[c][0], cells[c][1], cells[c][2], cells[c][3]});
    range_top[first / kRange] = top;
  });
  return range_top.empty() ? 0 : *std::max_element(range_top.begin(), range_top.end());
}

}  // namespace

std::vector<uint32_t> canonical_cell_order(std::span<const std::array<uint32_t, 4>> cells) {
  const size_t m = cells.size();
  std::vector<uint32_t> order;
  resize_on_every_core(order, m);
  // Every pass below runs on every core: at bunny_1m's level 0 (6.3M
  // cells) the four passes in order held about 0.2 s of the exact decode's
  // time on one thread. Whether the cells are in order already, by ranges.
  constexpr size_t kRange = size_t{1} << 16;
  std::vector<uint8_t> range_in_order((m + kRange - 1) / kRange, 1);
  parallel_ranges(m, kRange, [&](size_t first, size_t last) {
    bool in_order = true;
    for (size_t k = std::max<size_t>(first, 1); k < last && in_order; ++k)
      in_order = sorted4(cells[k - 1]) < sorted4(cells[k]);
    range_in_order[first / kRange] = in_order;
  });
  if (std::all_of(range_in_order.begin(), range_in_order.end(), [](uint8_t r) { return r != 0; })) {
    parallel_ranges(m, kRange, [&](size_t first, size_t last) {
      for (size_t k = first; k < last; ++k) order[k] = static_cast<uint32_t>(k);
    });
    return order;
  }
  // Each cell's other three vertices (sorted) and its index go straight to
  // its smallest vertex's bucket: one pass reading the cells in order, then
  // each bucket sorted where it lies. (Gathering the cells by index into
  // the buckets instead, a random read per cell, took 30% longer.) The
  // buckets are counted and filled through atomic cursors, so a bucket's
  // entries arrive in any order; sorting them by their vertices, then by
  // the cell's index, makes the order the same however they came. The
  // entries cost 16 bytes a cell while the triangulation is still held,
  // below the insertion's peak.
  struct Entry {
    uint32_t second, third, fourth, cell;
  };
  const size_t rows = size_t{largest_vertex(cells)} + 1;
  std::vector<uint32_t> start;
  resize_on_every_core(start, rows + 1);
  parallel_ranges(m, kRange, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      const auto& c = cells[k];
      atomic_fetch_add(start[size_t{std::min({c[0], c[1], c[2], c[3]})} + 1], 1);
    }
  });
  for (size_t v = 1; v <= rows; ++v) start[v] += start[v - 1];
  std::vector<Entry> entries;
  resize_on_every_core(entries, m);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    parallel_ranges(m, kRange, [&](size_t first, size_t last) {
      for (size_t k = first; k < last; ++k) {
        const auto c = sorted4(cells[k]);
        entries[atomic_fetch_add(fill[c[0]], 1)] = {c[1], c[2], c[3], static_cast<uint32_t>(k)};
      }
    });
  }
  constexpr size_t kBlock = 4096;
  parallel_for((rows + kBlock - 1) / kBlock,
               [&](size_t block) {
                 for (size_t v = block * kBlock; v < std::min(rows, block * kBlock + kBlock); ++v) {
                   Entry* first = entries.data() + start[v];
                   Entry* last = entries.data() + start[v + 1];
                   std::sort(first, last, [](const Entry& a, const Entry& b) {
                     return std::tie(a.second, a.third, a.fourth, a.cell) <
                            std::tie(b.second, b.third, b.fourth, b.cell);
                   });
                   for (Entry* e = first; e != last; ++e)
                     order[static_cast<size_t>(e - entries.data())] = e->cell;
                 }
               },
               2);
  return order;
}

void sort_as_boundary_triangles(std::vector<std::array<uint32_t, 3>>& faces) {
  const auto key = [](std::array<uint32_t, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  std::sort(faces.begin(), faces.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
}

std::vector<std::array<uint32_t, 3>> boundary_triangles(std::span<const std::array<uint32_t, 4>> cells,
                                                        size_t faces_per_pass) {
  // Outward faces of a positively oriented (a, b, c, d): d lies on the
  // right-hand normal side of (a, b, c), so that face turns the other way.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  if (cells.empty()) return {};
  // Each face's sorted vertices are its key. Faces are bucketed by their
  // smallest vertex, each entry holding the other two and the face's number,
  // then each small bucket is sorted on its own: the two sides of an inner
  // face meet in one bucket. The output is in ascending key order, as one
  // global sort would give, at a fraction of its cost. The entries are
  // sorted where they lie (sorting indices into a key array, this took 1.1 s
  // for bunny_1m's 6.3M tetrahedra; now 0.77 s), the buckets on every core.
  auto key_of = [&](size_t c, int f) {
    std::array<uint32_t, 3> key = {cells[c][kFaces[f][0]], cells[c][kFaces[f][1]], cells[c][kFaces[f][2]]};
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    if (key[1] > key[2]) std::swap(key[1], key[2]);
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    return key;
  };
  // The buckets' sizes and, below, their entries, on every core: a face's
  // place in its bucket is taken by an atomic count, so a bucket's order
  // varies from run to run, which nothing below sees.
  constexpr size_t kRange = size_t{1} << 16;
  const uint32_t top = largest_vertex(cells);
  std::vector<uint32_t> start(size_t{top} + 2, 0);
  parallel_ranges(cells.size(), kRange, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c)
      for (int f = 0; f < 4; ++f) atomic_fetch_add(start[size_t{key_of(c, f)[0]} + 1], 1);
  });
  for (size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  struct Entry {
    uint32_t second, third, face;  // the key's other two vertices; 4 * cell + face
  };
  // The buckets in passes of at most a sixteenth of the faces each (or
  // 2^22): the entries of every face at once took 12 bytes a face, 2.7 GB
  // for bunny_10m's 57M tetrahedra, the encoder's peak (an eighth, or 2^24,
  // still 200 MB at 1M vertices). Each pass reads every cell again and
  // keeps the faces of its buckets.
  const size_t buckets = start.size() - 1;
  const size_t budget =
      faces_per_pass > 0 ? faces_per_pass : std::max<size_t>(size_t{1} << 22, start.back() / 16 + 1);
  std::vector<std::vector<std::array<uint32_t, 3>>> found;
  std::vector<Entry> entries;
  for (size_t pass_first = 0; pass_first < buckets;) {
    size_t pass_end = pass_first + 1;
    while (pass_end < buckets && start[pass_end + 1] - start[pass_first] <= budget) ++pass_end;
    const uint32_t base = start[pass_first];
    // A larger pass than those before: no copy of the old entries (which
    // it overwrites) beside the new.
    if (start[pass_end] - base > entries.capacity()) release(entries);
    entries.resize(start[pass_end] - base);
    {
      // The pass's faces found in ranges of the cells on every core (each
      // pass reads every cell: serial, the passes took 1.2 s of bunny_1m's
      // encoder), each put in its bucket where it is found.
      std::vector<uint32_t> fill(start.begin() + static_cast<std::ptrdiff_t>(pass_first),
                                 start.begin() + static_cast<std::ptrdiff_t>(pass_end));
      parallel_ranges(cells.size(), kRange, [&](size_t first, size_t last) {
        for (size_t c = first; c < last; ++c)
          for (int f = 0; f < 4; ++f) {
            const auto key = key_of(c, f);
            if (key[0] < pass_first || key[0] >= pass_end) continue;
            entries[atomic_fetch_add(fill[key[0] - pass_first], 1) - base] = {
                key[1], key[2], static_cast<uint32_t>(4 * c + static_cast<size_t>(f))};
          }
      });
    }
    // Each block of buckets finds its boundary faces on its own; the
    // blocks' lists are joined in order.
    constexpr size_t kBlock = 8192;
    const size_t blocks = (pass_end - pass_first + kBlock - 1) / kBlock;
    const size_t first_block = found.size();
    found.resize(first_block + blocks);
    parallel_for(
        blocks,
        [&](size_t block) {
          const size_t from = pass_first + block * kBlock, to = std::min(pass_end, from + kBlock);
          for (size_t v = from; v < to; ++v) {
            Entry* const first = entries.data() + (start[v] - base);
            Entry* const last = entries.data() + (start[v + 1] - base);
            std::sort(first, last, [](const Entry& a, const Entry& b) {
              return a.second != b.second ? a.second < b.second : a.third < b.third;
            });
            for (Entry* e = first; e != last;) {
              Entry* same = e;
              while (same != last && same->second == e->second && same->third == e->third) ++same;
              if (same - e == 1) {
                const auto& cell = cells[e->face / 4];
                const int* f = kFaces[e->face % 4];
                found[first_block + block].push_back({cell[f[0]], cell[f[1]], cell[f[2]]});
              }
              e = same;
            }
          }
        },
        2);
    pass_first = pass_end;
  }
  release(entries);
  std::vector<std::array<uint32_t, 3>> out;
  size_t total = 0;
  for (const auto& f : found) total += f.size();
  out.reserve(total);
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  return out;
}

}  // namespace dtm
