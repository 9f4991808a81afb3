// bench_hierarchy: how much does the whole level-of-detail hierarchy cost
// compared with a single CGAL Delaunay tetrahedralization of the same points?
//
// Per model (bunny_10k, bunny_100k, bunny_1m; absent .node files are skipped):
//   CgalDelaunay/<m>  dtm::delaunay_tetrahedralize: one CGAL build + export to TetMesh
//   CgalRaw/<m>       the bare CGAL range insertion, no export, destruction not timed
//   Hierarchy/<m>     dtm::build_hierarchy's bare mechanism (HierarchyOptions'
//                     defaults: one independent set per level, alpha carving,
//                     no guards) at meshenc's recommended grid
//                     (--box 256 --qbits 14 --dmax 2)
//   Encode/<m>        dtm::encode as meshenc runs it, codec preset, with the
//                     model's .ele (when beside the .node) as the reference solid
//   EncodePaper/<m>   the same, EncodeOptions::paper()
//   Decode.../<m>     the codec preset's stream
// All run on the same points; loading and quantization are not timed. At the
// end two markdown tables give each time over one CGAL construction's.
// "Time" is wall time; "CPU" is the whole process's CPU time, so CPU > Time
// would mean the build used several threads.
//
// Usage:
//   bench_hierarchy [--data DIR] [benchmark flags]   DIR defaults to $DTM_BENCH_DATA, else .
//   bench_hierarchy --peak-memory MODEL.node [hierarchy|cgal]
//       builds once in this fresh process and prints the peak RSS (ru_maxrss)
//   bench_hierarchy --cgal-version
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/version.h>
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "core/hierarchy.h"
#include "mesh/delaunay.h"
#include "tools/formats/tetgen.h"

namespace {

constexpr const char* kModels[] = {"bunny_10k", "bunny_100k", "bunny_1m"};
constexpr int kQBits = 14;
constexpr double kBox = 256;   // largest extent after scaling (meshenc --box 256)
constexpr double kDmax = 2.0;  // boundary tolerance in scaled units (meshenc --dmax 2)

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using RawDT = CGAL::Delaunay_triangulation_3<K>;

struct Model {
  std::string name;
  std::vector<dtm::InputPoint> points;        // scaled to the 256 box
  std::vector<std::array<uint32_t, 4>> tets;  // the .ele beside the .node, if any
  dtm::QuantizedPoints q;
  dtm::HierarchyOptions opt;
  std::vector<uint8_t> stream;  // encoded once, on first use by a decode benchmark

  dtm::EncodeOptions options(bool paper) const {
    dtm::EncodeOptions o = paper ? dtm::EncodeOptions::paper() : dtm::EncodeOptions{};
    o.qbits = kQBits;
    o.dmax = kDmax;
    return o;
  }
  dtm::EncodedMesh encode(bool paper) const {
    dtm::EncodeInput in;
    in.points = points;
    in.tetrahedra = tets;
    return dtm::encode(in, options(paper)).value();
  }
  const std::vector<uint8_t>& encoded() {
    if (stream.empty()) stream = encode(false).bytes;
    return stream;
  }
};

// Same preprocessing as `meshenc FILE --box 256 --dmax 2`, so the benchmark
// times the run the README recommends.
Model load_model(const std::string& name, const std::string& path) {
  auto node = dtm::read_tetgen_node(path);
  const double extent = dtm::largest_extent(node.points);
  const double scale = extent > 0 ? kBox / extent : 1.0;
  for (auto& p : node.points) p = {p.x * scale, p.y * scale, p.z * scale};
  std::vector<std::array<uint32_t, 4>> tets;
  const std::string ele = std::filesystem::path(path).replace_extension(".ele").string();
  if (std::filesystem::exists(ele)) tets = dtm::read_tetgen_ele(ele, node.points.size(), node.index_base);

  Model m{name, node.points, std::move(tets), dtm::quantize(node.points, kQBits).value(), {}, {}};
  m.opt.dmax = kDmax / m.q.grid.step;  // HierarchyOptions wants grid units
  return m;
}

// Timing: a few iterations for the small models, one for the 1M model (each
// build takes seconds there, and run-to-run noise is small next to that).
int iterations_for(size_t n) { return n < 50'000 ? 10 : n < 500'000 ? 3 : 1; }

void register_benchmarks(const Model& m) {
  const int iters = iterations_for(m.q.points.size());
  const double n = static_cast<double>(m.q.points.size());

  benchmark::RegisterBenchmark(("CgalDelaunay/" + m.name).c_str(),
                               [&m, n](benchmark::State& st) {
                                 size_t cells = 0;
                                 for (auto _ : st) {
                                   const dtm::TetMesh dt = dtm::delaunay_tetrahedralize(m.q.points).value();
                                   cells = dt.cells.size();
                                   benchmark::DoNotOptimize(dt.cells.data());
                                 }
                                 st.counters["vertices"] = n;
                                 st.counters["cells"] = static_cast<double>(cells);
                               })
      ->Iterations(iters)
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime();

  // The wrapper above also attaches ids, numbers the cells and copies them
  // out; this variant shows what that export costs on top of CGAL itself.
  benchmark::RegisterBenchmark(("CgalRaw/" + m.name).c_str(),
                               [&m, n](benchmark::State& st) {
                                 std::vector<K::Point_3> pts;
                                 pts.reserve(m.q.points.size());
                                 for (const auto& p : m.q.points) pts.emplace_back(p.x, p.y, p.z);
                                 size_t cells = 0;
                                 for (auto _ : st) {
                                   auto dt = std::make_unique<RawDT>(pts.begin(),
                                                                     pts.end());  // spatial sort + insertion
                                   cells = dt->number_of_finite_cells();
                                   st.PauseTiming();  // freeing millions of cells is not construction
                                   dt.reset();
                                   st.ResumeTiming();
                                 }
                                 st.counters["vertices"] = n;
                                 st.counters["cells"] = static_cast<double>(cells);
                               })
      ->Iterations(iters)
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime();

  // The whole build as meshenc runs it, then without the boundary-error
  // statistics (a measurement: one AABB query per original boundary vertex
  // and level, which decides nothing).
  for (const bool stats : {true, false}) {
    const std::string name = (stats ? "Hierarchy/" : "HierarchyNoStats/") + m.name;
    benchmark::RegisterBenchmark(name.c_str(),
                                 [&m, n, stats](benchmark::State& st) {
                                   dtm::HierarchyOptions opt = m.opt;
                                   opt.measure_boundary_error = stats;
                                   size_t levels = 0, base = 0, level_vertices = 0;
                                   for (auto _ : st) {
                                     const dtm::Hierarchy h = dtm::build_hierarchy(m.q.points, opt).value();
                                     levels = h.levels.size();
                                     base = h.levels.back().vertices.size();
                                     level_vertices = 0;
                                     for (const auto& l : h.levels) level_vertices += l.vertices.size();
                                     benchmark::DoNotOptimize(h.levels.data());
                                   }
                                   st.counters["vertices"] = n;
                                   st.counters["levels"] = static_cast<double>(levels);  // including level 0
                                   st.counters["base_vertices"] = static_cast<double>(base);
                                   // Every level is analysed in full, so the work grows with the sum of
                                   // the level sizes (level 0 is tetrahedralized from scratch, the others
                                   // by refilling the removed vertices' cavities).
                                   st.counters["level_points_per_vertex"] =
                                       static_cast<double>(level_vertices) / n;
                                 })
        ->Iterations(iters)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
  }

  // What meshenc does after reading its input, reports included: each preset.
  for (const bool paper : {false, true}) {
    benchmark::RegisterBenchmark(((paper ? "EncodePaper/" : "Encode/") + m.name).c_str(),
                                 [&m, n, paper](benchmark::State& st) {
                                   size_t bytes = 0, levels = 0;
                                   for (auto _ : st) {
                                     const dtm::EncodedMesh e = m.encode(paper);
                                     bytes = e.bytes.size();
                                     levels = e.report.levels.size();
                                   }
                                   st.counters["vertices"] = n;
                                   st.counters["levels"] = static_cast<double>(levels);
                                   st.counters["bits_per_vertex"] = 8.0 * bytes / n;
                                 })
        ->Iterations(paper || n > 50'000 ? 1 : iters)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
  }

  // Every layer inserted, coarsest first, into one triangulation; then the
  // finest level's mesh exported and carved. Any level's mesh is available
  // the same way when its layer completes (next benchmark).
  benchmark::RegisterBenchmark(("Decode/" + m.name).c_str(),
                               [&m, n](benchmark::State& st) {
                                 const auto& bytes = const_cast<Model&>(m).encoded();
                                 size_t cells = 0;
                                 for (auto _ : st) {
                                   dtm::ProgressiveDecoder dec;
                                   if (!dec.feed(bytes).ok()) st.SkipWithError("decode failed");
                                   cells = dec.carved_cells().size();
                                 }
                                 st.counters["vertices"] = n;
                                 st.counters["carved_cells"] = static_cast<double>(cells);
                               })
      ->Iterations(iters)
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime();

  benchmark::RegisterBenchmark(
      ("DecodeEveryLevelMesh/" + m.name).c_str(),
      [&m, n](benchmark::State& st) {
        const auto& bytes = const_cast<Model&>(m).encoded();
        size_t cells = 0;
        for (auto _ : st) {
          dtm::ProgressiveDecoder dec;
          cells = 0;
          const auto s = dec.feed(bytes, [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel&) {
            cells += d.carved_cells().size();
          });
          if (!s.ok()) st.SkipWithError("decode failed");
        }
        st.counters["vertices"] = n;
        st.counters["carved_cells_all_levels"] = static_cast<double>(cells);
      })
      ->Iterations(iters)
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime();
}

// Prints the usual console output and keeps, per benchmark, the real time
// and the counters for the summary table.
class CollectingReporter : public benchmark::ConsoleReporter {
 public:
  struct Result {
    double seconds = 0;  // mean real time per iteration over all repetitions
    benchmark::UserCounters counters;
  };
  using ConsoleReporter::ConsoleReporter;

  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      // Aggregates (--benchmark_repetitions) would double count; errors have no time.
      if (r.run_type != Run::RT_Iteration || r.error_occurred || r.iterations == 0) continue;
      // function_name is the registered name, without the "/iterations:N" suffix.
      Sum& s = sums_[r.run_name.function_name];
      s.seconds += r.real_accumulated_time;
      s.iterations += r.iterations;
      s.counters = r.counters;
    }
  }
  std::optional<Result> find(const std::string& name) const {
    const auto it = sums_.find(name);
    if (it == sums_.end()) return std::nullopt;
    return Result{it->second.seconds / it->second.iterations, it->second.counters};
  }

 private:
  struct Sum {
    double seconds = 0;
    int64_t iterations = 0;
    benchmark::UserCounters counters;
  };
  std::map<std::string, Sum> sums_;
};

void print_codec_table(const CollectingReporter& rep, const std::vector<std::unique_ptr<Model>>& models) {
  std::printf(
      "\n| model | vertices | reference solid | CGAL DT (s) | encode, codec (s) | ratio | levels | bits per "
      "vertex "
      "| encode, paper (s) | ratio | levels | decode, finest mesh (s) | ratio "
      "| decode, every level's mesh (s) | ratio |\n"
      "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& m : models) {
    const auto cgal = rep.find("CgalDelaunay/" + m->name);
    const auto enc = rep.find("Encode/" + m->name);
    const auto paper = rep.find("EncodePaper/" + m->name);
    const auto dec = rep.find("Decode/" + m->name);
    const auto all = rep.find("DecodeEveryLevelMesh/" + m->name);
    if (!cgal || !enc || !paper || !dec || !all) continue;
    std::printf(
        "| %s | %zu | %s | %.3f | %.3f | %.1f | %.0f | %.2f | %.3f | %.1f | %.0f | %.3f | %.2f | %.3f | %.2f "
        "|\n",
        m->name.c_str(), m->q.points.size(), m->tets.empty() ? "level 0's alpha carving" : "its .ele",
        cgal->seconds, enc->seconds, enc->seconds / cgal->seconds, enc->counters.at("levels").value,
        enc->counters.at("bits_per_vertex").value, paper->seconds, paper->seconds / cgal->seconds,
        paper->counters.at("levels").value, dec->seconds, dec->seconds / cgal->seconds, all->seconds,
        all->seconds / cgal->seconds);
  }
}

void print_table(const CollectingReporter& rep, const std::vector<std::unique_ptr<Model>>& models) {
  std::printf(
      "\n| model | vertices | levels | CGAL DT (s) | hierarchy (s) | ratio | hierarchy without "
      "error statistics (s) | ratio | raw CGAL build (s) | sum of level sizes / N |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& m : models) {
    const auto cgal = rep.find("CgalDelaunay/" + m->name);
    const auto raw = rep.find("CgalRaw/" + m->name);
    const auto hier = rep.find("Hierarchy/" + m->name);
    const auto bare = rep.find("HierarchyNoStats/" + m->name);
    if (!cgal || !hier || !bare) continue;  // filtered out by --benchmark_filter, or failed
    char raw_text[32] = "-";
    if (raw) std::snprintf(raw_text, sizeof raw_text, "%.3f", raw->seconds);
    std::printf("| %s | %zu | %.0f | %.3f | %.3f | %.1f | %.3f | %.1f | %s | %.2f |\n", m->name.c_str(),
                m->q.points.size(), hier->counters.at("levels").value, cgal->seconds, hier->seconds,
                hier->seconds / cgal->seconds, bare->seconds, bare->seconds / cgal->seconds, raw_text,
                hier->counters.at("level_points_per_vertex").value);
  }
}

double max_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // Linux reports KiB
}

// One build in a fresh process: ru_maxrss is a high-water mark, so measuring
// several models (or the benchmark loop) in one process would mix them up.
int peak_memory(const std::string& path, const std::string& what) {
  if (what != "hierarchy" && what != "cgal") {
    std::fprintf(stderr, "bench_hierarchy: --peak-memory: expected 'hierarchy' or 'cgal'\n");
    return 2;
  }
  const Model m = load_model(std::filesystem::path(path).stem().string(), path);
  const double loaded = max_rss_mib();
  const auto start = std::chrono::steady_clock::now();
  size_t levels = 1;
  if (what == "cgal") {
    benchmark::DoNotOptimize(dtm::delaunay_tetrahedralize(m.q.points).value().cells.data());
  } else {
    levels = dtm::build_hierarchy(m.q.points, m.opt).value().levels.size();
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "model=%s build=%s vertices=%zu levels=%zu seconds=%.3f loaded_rss_mib=%.1f peak_rss_mib=%.1f\n",
      m.name.c_str(), what.c_str(), m.q.points.size(), levels, secs, loaded, max_rss_mib());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Our own flags are taken out of argv before Google Benchmark sees it.
  std::string data = std::getenv("DTM_BENCH_DATA") ? std::getenv("DTM_BENCH_DATA") : ".";
  std::vector<char*> rest = {argv[0]};
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--cgal-version") {
        std::printf("%s\n", CGAL_VERSION_STR);
        return 0;
      } else if (a == "--peak-memory" && i + 1 < argc) {
        return peak_memory(argv[i + 1], i + 2 < argc ? argv[i + 2] : "hierarchy");
      } else if (a == "--data" && i + 1 < argc) {
        data = argv[++i];
      } else if (a.rfind("--data=", 0) == 0) {
        data = a.substr(7);
      } else {
        rest.push_back(argv[i]);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_hierarchy: %s\n", e.what());
    return 1;
  }
  int bargc = static_cast<int>(rest.size());
  benchmark::Initialize(&bargc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(bargc, rest.data())) return 1;

  // Models live on the heap so the benchmark lambdas can hold references.
  std::vector<std::unique_ptr<Model>> models;
  for (const char* name : kModels) {
    const std::string path = data + "/" + name + ".node";
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr, "bench_hierarchy: skipping %s: %s not found\n", name, path.c_str());
      continue;
    }
    try {
      models.push_back(std::make_unique<Model>(load_model(name, path)));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_hierarchy: skipping %s: %s\n", name, e.what());
      continue;
    }
    register_benchmarks(*models.back());
  }
  if (models.empty()) {
    std::fprintf(stderr, "bench_hierarchy: no model found in %s (set DTM_BENCH_DATA or --data)\n",
                 data.c_str());
    return 1;
  }

  CollectingReporter rep(isatty(STDOUT_FILENO) ? benchmark::ConsoleReporter::OO_Color
                                               : benchmark::ConsoleReporter::OO_None);
  benchmark::RunSpecifiedBenchmarks(&rep);
  print_table(rep, models);
  print_codec_table(rep, models);
  benchmark::Shutdown();
  return 0;
}
