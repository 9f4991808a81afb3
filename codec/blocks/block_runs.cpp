#include "codec/blocks/block_runs.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <new>
#include <string>
#include <system_error>
#include <thread>

#include "codec/bricks/bricks.h"
#include "common/release.h"
#include "common/threads.h"

namespace dtm {

namespace {

// Appends the blocks of the box (bits, prefix) holding codes[begin, end),
// none empty.
void split_box(std::span<const MortonCode> codes, int qbits, int max_bits, uint64_t max_points, int bits,
               uint64_t prefix, size_t begin, size_t end, BlockPlan& p) {
  if (end - begin <= max_points || bits >= max_bits) {
    p.blocks.push_back(prefix);
    p.bits.push_back(bits);
    p.first.push_back(begin);
    return;
  }
  const int shift = 3 * qbits - bits - 1;
  const auto half = static_cast<size_t>(std::lower_bound(codes.begin() + static_cast<std::ptrdiff_t>(begin),
                                                         codes.begin() + static_cast<std::ptrdiff_t>(end),
                                                         MortonCode{2 * prefix + 1} << shift) -
                                        codes.begin());
  if (half > begin) split_box(codes, qbits, max_bits, max_points, bits + 1, 2 * prefix, begin, half, p);
  if (end > half) split_box(codes, qbits, max_bits, max_points, bits + 1, 2 * prefix + 1, half, end, p);
}

}  // namespace

GridBox BlockPlan::box(size_t k, int qbits) const {
  // The codes with this prefix are a box: its first and last corners.
  const int free = 3 * qbits - bits[k];
  const MortonCode first = MortonCode{blocks[k]} << free;
  const GridPoint lo = morton_decode(first, qbits),
                  hi = morton_decode(first + ((MortonCode{1} << free) - 1), qbits);
  return {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
}

BlockPlan plan_blocks(std::span<const MortonCode> codes, int qbits, int max_depth, uint64_t max_points,
                      int ranks) {
  BlockPlan p;
  if (!codes.empty())
    split_box(codes, qbits, 3 * max_depth, std::max<uint64_t>(1, max_points), 0, 0, 0, codes.size(), p);
  p.first.push_back(codes.size());
  assign_ranks(p, ranks);
  return p;
}

void assign_ranks(BlockPlan& p, int ranks) {
  const double share = static_cast<double>(p.first.back()) / ranks;
  p.rank.clear();
  for (size_t k = 0; k < p.blocks.size(); ++k) {
    const double middle = 0.5 * static_cast<double>(p.first[k] + p.first[k + 1]);
    p.rank.push_back(std::min(ranks - 1, static_cast<int>(middle / share)));
  }
}

void RankLoads::balance(BlockPlan& plan, int prefer) {
  const int ranks = static_cast<int>(points_.size());
  const bool few = plan.blocks.size() < points_.size();
  for (size_t k = 0; k < plan.blocks.size(); ++k) {
    if (plan.blocks.size() == 1 && prefer >= 0 && prefer < ranks) {
      plan.rank[k] = prefer;
    } else if (few) {
      // The least loaded; the lowest such rank on a tie.
      plan.rank[k] = static_cast<int>(std::min_element(points_.begin(), points_.end()) - points_.begin());
    }
    const int r = std::clamp(plan.rank[k], 0, ranks - 1);
    points_[static_cast<size_t>(r)] += plan.first[k + 1] - plan.first[k];
  }
}

void put(ByteWriter& w, std::span<const uint32_t> v) {
  w.u64(v.size());
  for (uint32_t x : v) w.u32(x);
}
void put(ByteWriter& w, std::span<const uint8_t> v) {
  w.u64(v.size());
  w.bytes(v);
}
void put(ByteWriter& w, const DistanceSums& d) {
  w.f64(d.max);
  w.f64(d.sum);
  w.u64(d.count);
}

uint8_t BlockReader::u8() {
  uint8_t v = 0;
  r_.u8(v);
  return v;
}
uint32_t BlockReader::u32() {
  uint32_t v = 0;
  r_.u32(v);
  return v;
}
uint64_t BlockReader::u64() {
  uint64_t v = 0;
  r_.u64(v);
  return v;
}
double BlockReader::f64() {
  double v = 0;
  r_.f64(v);
  return v;
}
std::vector<uint32_t> BlockReader::u32s() {
  std::vector<uint32_t> v(u64());
  for (uint32_t& x : v) x = u32();
  return v;
}
std::vector<uint8_t> BlockReader::bytes() {
  std::vector<uint8_t> v(u64());
  for (uint8_t& x : v) x = u8();
  return v;
}
DistanceSums BlockReader::sums() {
  DistanceSums d;
  d.max = f64();
  d.sum = f64();
  d.count = u64();
  return d;
}

std::vector<std::vector<uint8_t>> run_blocks(
    const BlockPlan& plan, RankExchange& exchange,
    const std::function<StatusOr<std::vector<uint8_t>>(size_t)>& work, Status& status, int at_once) {
  std::vector<size_t> mine;
  for (size_t k = 0; k < plan.blocks.size(); ++k)
    if (plan.rank[k] == exchange.rank()) mine.push_back(k);
  // A level of fewer blocks than ranks leaves ranks waiting: those at work
  // take their cores (the blocks' results do not depend on the threads).
  std::vector<uint8_t> busy(static_cast<size_t>(exchange.size()), 0);
  for (int r : plan.rank)
    if (r >= 0 && r < exchange.size()) busy[static_cast<size_t>(r)] = 1;
  const ThreadShare lent(exchange.threads_while_busy(busy));
  const auto run_one = [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
    try {
      return work(k);
    } catch (const std::bad_alloc&) {
      return Status{StatusCode::kLimitExceeded, "out of memory building a block"};
    } catch (const std::exception& e) {
      return Status{StatusCode::kInternal, e.what()};
    }
  };
  // Each of this rank's blocks' results, by its place in `mine`.
  std::vector<StatusOr<std::vector<uint8_t>>> done(mine.size(), Status{StatusCode::kInternal, "not run"});
  std::vector<uint8_t> ran(mine.size(), 0);
  const size_t workers = std::min<size_t>(static_cast<size_t>(std::max(1, at_once)), mine.size());
  if (workers <= 1) {
    for (size_t i = 0; i < mine.size(); ++i) {
      done[i] = run_one(mine[i]);
      ran[i] = 1;
      if (!done[i].ok()) break;
    }
  } else {
    // The blocks dealt out in order to whichever worker is free (their
    // sizes differ), each worker on its share of the threads; a worker left
    // without a block gives its share to those still building. After a
    // failure no later block starts, and every earlier one still runs: the
    // failure told is the first in block order, as one at a time would tell it.
    ThreadShares shares(thread_count(), static_cast<int>(workers));
    std::atomic<size_t> next{0};
    std::atomic<size_t> first_failed{mine.size()};
    const auto worker = [&](int w) {
      const ThreadShares::Use threads_of_blocks(shares, w);
      for (size_t i = next++; i < mine.size(); i = next++) {
        if (i > first_failed.load()) continue;
        done[i] = run_one(mine[i]);
        ran[i] = 1;
        if (done[i].ok()) continue;
        size_t f = first_failed.load();
        while (i < f && !first_failed.compare_exchange_weak(f, i)) {
          // f is now the index another worker set: lower it again if i is lower.
        }
      }
    };
    // The calling thread is one of the workers; a thread the system will
    // not start gives its share to the others at once.
    std::vector<std::thread> threads;
    for (size_t t = 1; t < workers; ++t) {
      try {
        threads.emplace_back(worker, static_cast<int>(t));
      } catch (const std::system_error&) {
        for (size_t never = t; never < workers; ++never) shares.end(static_cast<int>(never));
        break;
      }
    }
    worker(0);
    for (auto& t : threads) t.join();
  }
  // 1 and the results, or 0, the failure's code and its message.
  ByteWriter sent;
  sent.u8(1);
  Status local = Status::Ok();
  for (size_t i = 0; i < mine.size(); ++i) {
    if (!ran[i]) continue;  // after the first failure: not run
    if (!done[i].ok()) {
      local = done[i].status();
      break;
    }
    sent.u64(mine[i]);
    put(sent, std::span<const uint8_t>(*done[i]));
    release(*done[i]);
  }
  release(done);
  if (!local.ok()) {
    sent = ByteWriter();
    sent.u8(0);
    sent.u32(static_cast<uint32_t>(local.code()));
    const std::string& m = local.message();
    put(sent, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(m.data()), m.size()));
  }
  std::vector<std::vector<uint8_t>> all = exchange.all_gather(sent.take());
  std::vector<std::vector<uint8_t>> out(plan.blocks.size());
  // Each rank's bytes freed once read: a level's results are not held twice.
  for (auto& bytes : all) {
    if (bytes.empty()) continue;
    BlockReader r(std::span<const uint8_t>(bytes).subspan(1));
    if (bytes[0] == 0) {
      const auto code = static_cast<StatusCode>(r.u32());
      const std::vector<uint8_t> m = r.bytes();
      if (status.ok()) status = {code, std::string(m.begin(), m.end())};
      continue;
    }
    while (!r.done()) {
      const uint64_t k = r.u64();
      out[k] = r.bytes();
    }
    release(bytes);
  }
  if (!local.ok()) status = local;
  return out;
}

std::vector<uint8_t> serialize(const BlockAnalysis& a) {
  ByteWriter w;
  const BlockFigures& f = a.figures;
  w.u64(f.vertices);
  w.u64(f.boundary_vertices);
  w.u64(f.cells);
  w.f64(f.quality_sum);
  w.f64(f.quality_min);
  put(w, f.to_level);
  put(w, f.to_reference);
  w.u64(f.cell_hash);
  w.u64(f.dropped_thick);
  w.f64(f.dropped_thick_radius);
  w.u64(f.cells_from_input);
  w.u64(f.cells_from_nearest);
  w.u64(f.tagged_faces_kept);
  w.u64(a.surface_triangles.size());
  for (const auto& t : a.surface_triangles)
    for (uint32_t v : t) w.u32(v);
  put(w, std::span<const uint32_t>(a.surface_vertices));
  w.u64(a.reference_squared.size());
  for (const auto& [id, d2] : a.reference_squared) w.u32(id), w.f64(d2);
  for (const auto* sections : {&a.carving, &a.regions, &a.faces, &a.cell_values}) {
    w.u64(sections->size());
    for (const auto& [brick, bytes] : *sections) {
      w.u64(brick);
      put(w, std::span<const uint8_t>(bytes));
    }
  }
  w.u64(a.cell_field_bytes.size());
  for (uint64_t b : a.cell_field_bytes) w.u64(b);
  put(w, std::span<const uint32_t>(a.chosen));
  put(w, std::span<const uint32_t>(a.boundary));
  w.u64(a.carved.size());
  for (const auto& c : a.carved)
    for (uint32_t v : c) w.u32(v);
  return w.take();
}

BlockAnalysis deserialize_analysis(std::span<const uint8_t> bytes) {
  BlockReader r(bytes);
  BlockAnalysis a;
  BlockFigures& f = a.figures;
  f.vertices = r.u64();
  f.boundary_vertices = r.u64();
  f.cells = r.u64();
  f.quality_sum = r.f64();
  f.quality_min = r.f64();
  f.to_level = r.sums();
  f.to_reference = r.sums();
  f.cell_hash = r.u64();
  f.dropped_thick = r.u64();
  f.dropped_thick_radius = r.f64();
  f.cells_from_input = r.u64();
  f.cells_from_nearest = r.u64();
  f.tagged_faces_kept = r.u64();
  a.surface_triangles.resize(r.u64());
  for (auto& t : a.surface_triangles)
    for (uint32_t& v : t) v = r.u32();
  a.surface_vertices = r.u32s();
  a.reference_squared.resize(r.u64());
  for (auto& [id, d2] : a.reference_squared) id = r.u32(), d2 = r.f64();
  for (auto* sections : {&a.carving, &a.regions, &a.faces, &a.cell_values}) {
    sections->resize(r.u64());
    for (auto& [brick, section] : *sections) brick = r.u64(), section = r.bytes();
  }
  a.cell_field_bytes.resize(r.u64());
  for (uint64_t& b : a.cell_field_bytes) b = r.u64();
  a.chosen = r.u32s();
  a.boundary = r.u32s();
  a.carved.resize(r.u64());
  for (auto& c : a.carved)
    for (uint32_t& v : c) v = r.u32();
  return a;
}

}  // namespace dtm
