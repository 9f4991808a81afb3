// bench_hierarchy: how much do the encoder and the decoder cost compared
// with one sequential CGAL Delaunay tetrahedralization of the same points?
//
// Per model (bunny_10k, bunny_100k, bunny_1m; absent .node files are skipped):
//   CgalSequential/<m>  CGAL's sequential range insertion (spatial sort +
//                       insertion), no export, destruction not timed: the
//                       reference every ratio divides by
//   CgalDelaunay/<m>    dtm::delaunay_tetrahedralize: the same points on every
//                       core (Parallel_tag) and exported to a TetMesh
//   Encode/<m>          dtm::encode as meshenc runs it (reports included),
//                       codec preset, the model's .ele (when beside the .node)
//                       as the reference solid, at meshenc's recommended grid
//                       (--box 256 --qbits 14 --dmax 2)
//   EncodePaper/<m>     the same, EncodeOptions::paper() (10k and 100k only:
//                       the paper preset is exempt from the speed target)
//   Decode.../<m>       the codec preset's stream: the finest mesh, every mesh
// All run on the same points; loading and quantization are not timed. At the
// end a markdown table gives each time over one sequential construction's.
// "Time" is wall time; "CPU" is the whole process's CPU time, so CPU > Time
// means several threads worked.
//
// Usage:
//   bench_hierarchy [--data DIR] [benchmark flags]   DIR defaults to $DTM_BENCH_DATA, else .
//   bench_hierarchy --peak-memory MODEL.node encode|decode|cgal
//       in this fresh process: loads the model (and, for decode, encodes it
//       first in a child process's stead: the stream is read from
//       MODEL.dtm, which `encode` writes), does the one thing, and prints the
//       peak RSS (ru_maxrss) and the time
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
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "mesh/delaunay.h"
#include "tools/formats/tetgen.h"
#include "tools/huge_pages.h"

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

  return Model{name, node.points, std::move(tets), dtm::quantize(node.points, kQBits).value(), {}};
}

// Timing: a few iterations for the small models, one for the 1M model (each
// build takes seconds there, and run-to-run noise is small next to that).
int iterations_for(size_t n) { return n < 50'000 ? 10 : n < 500'000 ? 3 : 1; }

void register_benchmarks(const Model& m) {
  const int iters = iterations_for(m.q.points.size());
  const double n = static_cast<double>(m.q.points.size());

  // The reference: CGAL alone, one thread.
  benchmark::RegisterBenchmark(("CgalSequential/" + m.name).c_str(),
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

  // Ours: on every core, and exported to a TetMesh.
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

  // What meshenc does after reading its input, reports included: each preset.
  for (const bool paper : {false, true}) {
    if (paper && n > 500'000) continue;
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
      "\n| model | vertices | reference solid | one sequential CGAL construction (s) | ours, both cores, "
      "exported | encode, codec | levels | bits per vertex | encode, paper | levels | decode, finest mesh "
      "| decode, every level's mesh |\n"
      "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& m : models) {
    const auto seq = rep.find("CgalSequential/" + m->name);
    const auto ours = rep.find("CgalDelaunay/" + m->name);
    const auto enc = rep.find("Encode/" + m->name);
    const auto paper = rep.find("EncodePaper/" + m->name);
    const auto dec = rep.find("Decode/" + m->name);
    const auto all = rep.find("DecodeEveryLevelMesh/" + m->name);
    if (!seq || !ours || !enc || !dec || !all) continue;
    auto ratio = [&](const auto& r) {
      char text[64];
      std::snprintf(text, sizeof text, "%.2fx (%.3f s)", r->seconds / seq->seconds, r->seconds);
      return std::string(text);
    };
    std::printf("| %s | %zu | %s | %.3f | %s | **%s** | %.0f | %.2f | %s | %s | **%s** | %s |\n",
                m->name.c_str(), m->q.points.size(), m->tets.empty() ? "level 0's alpha carving" : "its .ele",
                seq->seconds, ratio(ours).c_str(), ratio(enc).c_str(), enc->counters.at("levels").value,
                enc->counters.at("bits_per_vertex").value, paper ? ratio(paper).c_str() : "-",
                paper ? std::to_string(static_cast<int>(paper->counters.at("levels").value)).c_str() : "-",
                ratio(dec).c_str(), ratio(all).c_str());
  }
}

double max_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // Linux reports KiB
}

// One thing in a fresh process: ru_maxrss is a high-water mark, so
// measuring several models (or the benchmark loop) in one process would mix
// them up.
int peak_memory(const std::string& path, const std::string& what) {
  if (what != "encode" && what != "decode" && what != "cgal") {
    std::fprintf(stderr, "bench_hierarchy: --peak-memory: expected 'encode', 'decode' or 'cgal'\n");
    return 2;
  }
  const std::string stream_path = std::filesystem::path(path).replace_extension(".dtm").string();
  std::vector<uint8_t> stream;
  std::optional<Model> m;
  if (what == "decode") {
    std::ifstream in(stream_path, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "bench_hierarchy: %s missing: run --peak-memory %s encode first\n",
                   stream_path.c_str(), path.c_str());
      return 2;
    }
    stream.assign(std::istreambuf_iterator<char>(in), {});
  } else {
    m.emplace(load_model(std::filesystem::path(path).stem().string(), path));
  }
  const double loaded = max_rss_mib();
  const auto start = std::chrono::steady_clock::now();
  size_t levels = 1, vertices = 0;
  if (what == "cgal") {
    std::vector<K::Point_3> pts;
    for (const auto& p : m->q.points) pts.emplace_back(p.x, p.y, p.z);
    const RawDT dt(pts.begin(), pts.end());
    vertices = dt.number_of_vertices();
  } else if (what == "encode") {
    const dtm::EncodedMesh e = m->encode(false);
    levels = e.report.levels.size();
    vertices = m->q.points.size();
    std::ofstream(stream_path, std::ios::binary)
        .write(reinterpret_cast<const char*>(e.bytes.data()), static_cast<std::streamsize>(e.bytes.size()));
  } else {
    dtm::ProgressiveDecoder dec;
    if (!dtm::decode_stream(stream, dec).ok()) return 1;
    benchmark::DoNotOptimize(dec.carved_cells().data());
    levels = dec.levels().size();
    vertices = dec.points().size();
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "model=%s build=%s vertices=%zu levels=%zu seconds=%.3f loaded_rss_mib=%.1f peak_rss_mib=%.1f\n",
      std::filesystem::path(path).stem().c_str(), what.c_str(), vertices, levels, secs, loaded,
      max_rss_mib());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // As the tools run (tools/huge_pages.h), the CGAL construction it is
  // compared with too.
  dtm::ask_for_huge_pages(argv);
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
  print_codec_table(rep, models);
  benchmark::Shutdown();
  return 0;
}
