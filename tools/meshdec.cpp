// meshdec: decodes a .dtm stream (or any prefix of one) to a tetrahedral
// mesh file at the requested level of detail.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "codec/decode.h"
#include "codec/region_decode.h"
#include "mesh/geometry.h"
#include "tools/atomic_file.h"
#include "tools/decoded_mesh.h"
#include "tools/field_types.h"
#include "tools/formats/abaqus.h"
#include "tools/formats/exodus.h"
#include "tools/formats/gltf_writer.h"
#include "tools/formats/gmsh.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/netgen_vol.h"
#include "tools/formats/surface_writers.h"
#include "tools/huge_pages.h"
#include "tools/mpi_session.h"
#include "tools/phase_display.h"
#include "tools/same_command.h"
#include "tools/stream_input.h"
#include "tools/thread_budget.h"
#include "tools/tool_main.h"

namespace {

constexpr const char* kExamples = R"(
Examples:
  meshdec bunny.dtm -o bunny.vtu                 # finest level, for ParaView
  meshdec bunny.dtm -o coarse.node --level 3     # TetGen .node + .ele
  meshdec bunny.dtm -o bunny.msh                 # gmsh 4.1 (also .vtk, .mesh, Netgen's .vol)
  meshdec bunny.dtm -o surface.ply --level 3     # the boundary surface, normals out
  meshdec bunny.dtm -o bunny.glb --level 2       # the same as glTF 2.0, Draco-compressed (web, AR, Blender)
  meshdec ct.dtm -o ct.glb --color value         # coloured by the field 'value'
  meshdec part.dtm -o part.glb --color region    # each material's surface, a glTF material each
  meshdec bunny.dtm -o bunny.drc                 # the surface as a Draco file
  meshdec big.dtm -o part.vtu --box 0 0 0 10 10 10   # the cells meeting a box (reads only the
                                                  # chunks around it from a meshenc --bricks stream)
  mpirun -n 4 meshdec big.dtm -o big.pvtu         # one piece per rank (a --bricks stream), for ParaView
  meshdec big.dtm -o big.pvtu --pieces 4          # the same four pieces, one after another
  head -c 40000 bunny.dtm | meshdec - -o preview.vtu
  meshdec bunny.dtm -o - --format vtu > bunny.vtu

The stream's per-vertex fields (meshinfo lists them) are written beside the
points where the format has room: VTU/VTK point data in their own types, gmsh
$NodeData, PLY vertex properties, TetGen attributes.

A truncated stream decodes to the finest whole level it holds (exit status 0,
a note on stderr); a damaged or foreign one is an error and writes nothing.)";

struct Command {
  std::string input, output, format_name;
  int level = -1;
  bool verify = false, quiet = false, verbose = false;
  dtm::SurfaceStyle style;
  bool no_draco = false, colour_given = false;
  uint64_t max_vertices = dtm::DecoderOptions{}.max_vertices;
  std::vector<double> box;
  int pieces = 0;
  int threads = 0;  // --threads; 0: the process's share of its cores
};

void add_options(CLI::App& app, Command& c) {
  app.add_option("input", c.input, ".dtm stream ('-' = standard input)")->required();
  app.add_option(
         "-o,--output", c.output,
         "output: X.vtu, X.vtk, X.mesh, X.msh, X.vol, X.inp, X.e, X.node (+ X.ele); the boundary surface "
         "as X.ply, "
         "X.off, X.glb, X.gltf (+ X.bin) or X.drc; the points as X.xyz; '-' = standard output")
      ->required();
  app.add_option("--level", c.level, "level of detail to write (0 = finest; default: the finest present)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--format", c.format_name,
                 std::string(dtm::kOutputFormatNames) + " (default: from the output's extension)")
      ->check(CLI::IsMember({"node", "vtu", "vtu-ascii", "vtk", "vtk-ascii", "mesh", "msh", "vol", "inp", "e",
                             "ply", "off", "xyz", "glb", "gltf", "drc"}));
  app.add_option(
         "--color", c.style.colour,
         "glTF and .drc vertex colours: level (dark = coarsest), boundary, or a field's name (a vector by "
         "its length), on a colour ramp; or region: each region's own surface in its colour (glTF: a "
         "primitive each, its material named as the region)")
      ->capture_default_str()
      ->each([&c](const std::string&) { c.colour_given = true; });
  app.add_flag("--no-draco", c.no_draco, "glTF: plain buffers instead of Draco compression");
  app.add_flag("--verify", c.verify,
               "check every decoded level against the cell-set hashes in the stream (meshenc --hash-cells)");
  app.add_option("--max-vertices", c.max_vertices, "refuse streams claiming more vertices than this")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) {
            return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos &&
                           text.find_first_not_of('0') != std::string::npos
                       ? std::string()
                       : "must be a whole number above 0, got '" + text + "'";
          },
          "N>0"));
  app.add_option("--box", c.box,
                 "only the level's cells that meet this box (their bounding boxes do), in the input's units, "
                 "with point data vertex_id (the vertex's number in the whole level); from a bricked stream "
                 "(meshenc --bricks) it reads only the chunks around the box")
      ->expected(6)
      ->type_name("X0 Y0 Z0 X1 Y1 Z1");
  app.add_option(
         "--pieces", c.pieces,
         "with -o X.pvtu: decode the level in this many pieces, X_0.vtu ... (default: one per MPI rank "
         "under mpirun, else 1); every cell is in exactly one piece (a bricked stream: meshenc --bricks)")
      ->check(CLI::Range(1, 1 << 20));
  app.add_flag("-q,--quiet", c.quiet, "no notes on stderr (nor the progress line on a terminal)");
  app.add_flag("-v,--verbose", c.verbose,
               "print each phase of the work as it ends, with its time and the memory in use (now and at "
               "the peak so far)");
  dtm::add_threads_option(app, c.threads);
}

dtm::MeshFormat output_format(const Command& c) {
  dtm::MeshFormat format;
  if (!c.format_name.empty())
    format = dtm::format_named(c.format_name);
  else if (c.output == "-")
    format = dtm::MeshFormat::kVtu;
  else
    format = dtm::format_for_path(c.output);
  if (c.output == "-" && format == dtm::MeshFormat::kTetgen)
    throw dtm::UsageError("TetGen output is two files; it cannot go to standard output");
  if (c.output == "-" && format == dtm::MeshFormat::kGltf)
    throw dtm::UsageError("glTF output is two files (.gltf and .bin); write .glb to standard output");
  return format;
}

// --verify: every decoded level's mesh against the cell-set hash the encoder stored.
class Verifier {
 public:
  void check(const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& l) {
    if (!error_.ok()) return;
    if (!l.cell_hash) {
      error_ = {dtm::StatusCode::kUnsupported,
                "--verify: the stream has no cell-set hashes (encode with meshenc --hash-cells)"};
      return;
    }
    const auto cells = d.carved_cells();
    if (!d.mesh_status().ok()) {
      error_ = d.mesh_status();
      return;
    }
    if (dtm::level_cell_hash(d.header().flags, d.points(), cells) != *l.cell_hash)
      error_ = {dtm::StatusCode::kCorrupt, "--verify: level " + std::to_string(l.level) +
                                               " differs from the encoder's mesh (a different Delaunay "
                                               "implementation?)"};
    else
      ++verified_;
  }
  const dtm::Status& error() const { return error_; }
  int verified() const { return verified_; }

 private:
  int verified_ = 0;
  dtm::Status error_;
};

// Feeds the input to the decoder as it is read; throws on anything but a
// whole or truncated stream with at least one level.
void decode(const Command& c, dtm::ProgressiveDecoder& decoder, Verifier& verifier,
            dtm::PhaseDisplay& display) {
  auto on_level = [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& l) {
    if (c.verify) verifier.check(d, l);
  };
  dtm::read_in_chunks(c.input, [&](std::span<const uint8_t> chunk) {
    // Read to the end: trailing bytes are an error.
    return decoder.feed(chunk, on_level).ok() && !decoder.stopped();
  });
  display.clear();
  const dtm::Status status = decoder.finish();
  // (The decoder refuses a level its header does not have as soon as it
  // reads the header.)
  if (c.level >= 0 && decoder.has_header() && c.level >= decoder.header().level_count)
    throw std::runtime_error(c.input + ": --level " + std::to_string(c.level) +
                             " asked, the stream has levels 0 to " +
                             std::to_string(decoder.header().level_count - 1));
  if (status.code() != dtm::StatusCode::kOk && status.code() != dtm::StatusCode::kTruncated)
    throw std::runtime_error(c.input + ": " + status.message());
  if (!verifier.error().ok()) throw std::runtime_error(c.input + ": " + verifier.error().message());
  if (decoder.finest_level() < 0) throw std::runtime_error(c.input + ": " + status.message());
  // A level asked for that a truncated stream does not reach is an error,
  // as one the stream never had is: not a coarser level in its place.
  if (c.level >= 0 && decoder.finest_level() > c.level)
    throw std::runtime_error(c.input + ": --level " + std::to_string(c.level) + " asked, but " +
                             status.message());
  if (status.code() == dtm::StatusCode::kTruncated && !c.quiet)
    std::fprintf(stderr, "meshdec: %s: truncated: %s; writing level %d\n", c.input.c_str(),
                 status.message().c_str(), decoder.finest_level());
}

// The labels and names `format` writes otherwise than the stream has them
// (Exodus and gmsh ids are positive, Exodus names unique, Abaqus labels
// and Netgen names one word, Netgen's numbers its own).
std::vector<std::string> written_otherwise(const dtm::OutputMesh& mesh, dtm::MeshFormat format) {
  switch (format) {
    case dtm::MeshFormat::kExodus:
      return dtm::exodus_renumbering(mesh);
    case dtm::MeshFormat::kGmsh:
      return dtm::gmsh_renumbering(mesh);
    case dtm::MeshFormat::kAbaqus:
      return dtm::abaqus_renaming(mesh);
    case dtm::MeshFormat::kNetgen:
      return dtm::netgen_renumbering(mesh);
    default:
      return {};
  }
}

void write_output(const Command& c, const dtm::OutputMesh& mesh, dtm::MeshFormat format) {
  dtm::SurfaceStyle style = c.style;
  style.draco = !c.no_draco;
  const auto files = dtm::render_mesh(mesh, format, c.output == "-" ? "out.vtu" : c.output, style);
  // Nothing of the stream's data dropped without a word.
  if (!c.quiet)
    for (const std::string& what : dtm::not_written(mesh, format, style))
      std::fprintf(stderr, "meshdec: %s: not written (the format has no place for it): %s\n",
                   c.output.c_str(), what.c_str());
  // (The input's node ids, 22.0: only the gmsh, Abaqus and Exodus files
  // number their nodes.)
  if (!c.quiet && !mesh.node_labels.empty() && format != dtm::MeshFormat::kGmsh &&
      format != dtm::MeshFormat::kAbaqus && format != dtm::MeshFormat::kExodus)
    std::fprintf(stderr,
                 "meshdec: %s: not written (the format has no place for it): the input's node ids (the nodes "
                 "are in the input's order; .msh, .inp and .e number them with their ids)\n",
                 c.output.c_str());
  // What the format numbers or names otherwise than the stream: said, each.
  if (!c.quiet)
    for (const std::string& what : written_otherwise(mesh, format))
      std::fprintf(stderr, "meshdec: %s: written with another id or name: %s\n", c.output.c_str(),
                   what.c_str());
  if (c.output != "-") return dtm::write_files_atomically(files);
  const std::string& bytes = files.front().second;
  if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() || std::fflush(stdout) != 0)
    throw std::runtime_error("cannot write to standard output");
}

// A region or a piece of the level asked for; without --level, of a
// truncated stream's finest whole level, as the whole decode gives (level
// 0 tried, then each coarser one while the stream ends before the one
// tried; `levels`: the header's count, 0 if it did not parse). Says so.
template <class Decode>
auto of_finest_whole_level(const Command& c, int levels, Decode&& decode) {
  int level = std::max(c.level, 0);
  auto got = decode(level);
  const dtm::Status first = got.status();
  while (c.level < 0 && !got.ok() && got.status().code() == dtm::StatusCode::kTruncated && level + 1 < levels)
    got = decode(++level);
  if (got.ok() && level > 0 && c.level < 0 && !c.quiet)
    std::fprintf(stderr, "meshdec: %s: truncated: %s; writing level %d\n", c.input.c_str(),
                 first.message().c_str(), level);
  return std::pair{level, std::move(got)};
}

// -o X.pvtu: the level in pieces X_0.vtu, X_1.vtu, ..., each rank writing
// its own (ranks take pieces in turn), rank 0 the .pvtu with its own. Every
// file is staged beside its target, and put in place once every rank has
// staged its own: any rank's failure fails them all and leaves the files
// as they were (an earlier run's pieces and .pvtu included).
int run_pieces(const Command& c) {
  dtm::MpiSession& mpi = dtm::mpi_session();
  if (c.input == "-") throw dtm::UsageError("-o X.pvtu reads the stream by offset: give a file, not '-'");
  if (!c.box.empty() || c.verify)
    throw dtm::UsageError(
        "-o X.pvtu writes a whole level in pieces: --box and --verify are for one file's output");
  const int pieces = c.pieces > 0 ? c.pieces : mpi.size();
  int level = std::max(c.level, 0);
  const std::string stem = c.output.substr(0, c.output.size() - 5);
  const size_t slash = stem.find_last_of('/');
  const std::string base = slash == std::string::npos ? stem : stem.substr(slash + 1);
  std::vector<std::string> names;
  names.reserve(static_cast<size_t>(pieces));
  dtm::StagedFiles staged;
  bool any_written = false;
  for (int i = 0; i < pieces; ++i) names.push_back(base + "_" + std::to_string(i) + ".vtu");
  std::string error;
  uint64_t cells = 0, bytes_read = 0, largest_read = 0, size = 0, empty = 0;
  dtm::Grid grid;
  dtm::OutputMesh like;  // the arrays of the first piece written here (every piece has them)
  dtm::PhaseDisplay display(
      !c.quiet && isatty(STDERR_FILENO), c.verbose && !c.quiet,
      mpi.size() > 1 ? "rank " + std::to_string(mpi.rank()) + "/" + std::to_string(mpi.size()) + ": " : "");
  try {
    auto source = dtm::FileSource::open(c.input);
    if (!source.ok()) throw std::runtime_error(source.status().message());
    size = source->size();
    dtm::DecoderOptions options;
    options.max_vertices = c.max_vertices;
    options.on_phase = [&](std::string_view phase) { display.start(phase); };
    // The grid the pieces' points map back through (decode_piece says what
    // is wrong with a header that does not parse).
    std::vector<uint8_t> head(dtm::kHeaderSize);
    dtm::StreamHeader header;
    if (size >= head.size() && source->read(0, head).ok() && dtm::parse_header(head, header).ok())
      grid = header.grid;
    for (int i = mpi.rank(); i < pieces; i += mpi.size()) {
      // (This rank's first piece finds the level of a truncated stream;
      // every rank finds the same, and rank 0 says so.)
      Command finding = c;
      finding.quiet = c.quiet || mpi.rank() != 0;
      if (i != mpi.rank()) finding.level = level;
      auto found = of_finest_whole_level(finding, header.level_count, [&](int l) {
        return dtm::decode_piece(*source, l, i, pieces, options);
      });
      level = found.first;
      auto& piece = found.second;
      if (!piece.ok()) throw std::runtime_error(c.input + ": " + piece.status().message());
      const std::string path = (slash == std::string::npos ? "" : stem.substr(0, slash + 1)) + names[i];
      display.start("writing " + path);
      dtm::OutputMesh mesh = dtm::region_output(*piece, grid);
      staged.stage(dtm::render_mesh(mesh, dtm::MeshFormat::kVtu, path));
      // What a .vtu has no place for (the regions' and tags' names), said
      // once, of piece 0: every piece has the stream's tables.
      if (i == 0 && !c.quiet) {
        display.clear();
        for (const std::string& what : dtm::not_written(mesh, dtm::MeshFormat::kVtu))
          std::fprintf(stderr, "meshdec: %s: not written (the format has no place for it): %s\n",
                       c.output.c_str(), what.c_str());
      }
      if (!any_written) {
        like.declare_level = true;
        like.declare_region = mesh.declare_region;
        like.fields = std::move(mesh.fields);
        like.cell_fields = std::move(mesh.cell_fields);
      }
      any_written = true;
      cells += piece->cells.size();
      empty += piece->cells.empty();
      bytes_read += piece->bytes_read;
      largest_read = std::max(largest_read, piece->bytes_read);
    }
    // (Rank 0 staged piece 0: its arrays are every piece's.)
    if (mpi.rank() == 0) staged.stage({{c.output, dtm::render_pvtu(like, names)}});
  } catch (const std::exception& e) {
    error = e.what();
  }
  // Errors are printed by rank 0, each once: one every rank met alike (a
  // stream that is not there, damaged, not bricked) as it is, others with
  // the ranks that met them. (The staged files are removed as `staged` goes.)
  const auto fail_together = [&mpi](const std::string& mine) {
    const auto errors = mpi.all_gather({reinterpret_cast<const uint8_t*>(mine.data()), mine.size()});
    const bool alike = std::all_of(errors.begin(), errors.end(),
                                   [&](const std::vector<uint8_t>& e) { return e == errors.front(); });
    if (alike) throw dtm::AgreedError(mine, mpi.rank() == 0);
    // Else each error once, by rank 0, with the ranks that met it.
    std::vector<std::pair<std::string, std::string>> said;  // (error, its ranks)
    for (size_t r = 0; r < errors.size(); ++r) {
      if (errors[r].empty()) continue;
      const std::string e(errors[r].begin(), errors[r].end());
      const auto it = std::find_if(said.begin(), said.end(), [&](const auto& s) { return s.first == e; });
      if (it == said.end())
        said.emplace_back(e, std::to_string(r));
      else
        it->second += ", " + std::to_string(r);
    }
    std::string all;
    for (const auto& [e, ranks] : said)
      all += (all.empty() ? "" : "; ") +
             std::string(ranks.find(',') == std::string::npos ? "rank " : "ranks ") + ranks + ": " + e;
    throw dtm::AgreedError(all, mpi.rank() == 0);
  };
  if (!mpi.all(error.empty())) fail_together(error);
  // Every rank's files in place, or none: a rank whose renames succeeded
  // puts back what they replaced where another's failed.
  try {
    staged.commit();
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi.all(error.empty())) {
    staged.undo();
    fail_together(error);
  }
  display.finish();
  const uint64_t all_cells = mpi.sum(cells), all_read = mpi.sum(bytes_read), all_empty = mpi.sum(empty);
  if (mpi.rank() == 0) {
    if (!c.quiet)
      std::fprintf(
          stderr,
          "meshdec: level %d: %d piece%s (%d rank%s), %llu tetrahedra; the pieces read %llu bytes of a "
          "%llu-byte stream in all\n",
          level, pieces, pieces == 1 ? "" : "s", mpi.size(), mpi.size() == 1 ? "" : "s",
          static_cast<unsigned long long>(all_cells), static_cast<unsigned long long>(all_read),
          static_cast<unsigned long long>(size));
    // (A piece is a range of whole chunks: more pieces than the level has
    // chunks leave some empty.)
    if (!c.quiet && all_empty > 0)
      std::fprintf(stderr,
                   "meshdec: %llu of the %d pieces hold no cell (the level has fewer chunks than pieces, or "
                   "none there)\n",
                   static_cast<unsigned long long>(all_empty), pieces);
    // Pieces beyond these (an earlier run's, with more) are not the .pvtu's:
    // said, for a count over X_*.vtu would take their cells twice.
    std::string beyond;
    std::error_code ec;
    for (int i = pieces;; ++i) {
      const std::string path = (slash == std::string::npos ? "" : stem.substr(0, slash + 1)) + base + "_" +
                               std::to_string(i) + ".vtu";
      if (!std::filesystem::exists(path, ec)) break;
      beyond += (beyond.empty() ? "" : ", ") + path;
    }
    if (!c.quiet && !beyond.empty())
      std::fprintf(stderr, "meshdec: %s: not pieces of %s (an earlier run's?): left as they are\n",
                   beyond.c_str(), c.output.c_str());
  }
  return 0;
}

// A box that meets no cell is said, and nothing written: a mesh file
// without cells is one that gmsh, meshio and the surface writers refuse.
// Where the mesh is, for the next box: the bounds of `points` (grid
// points), which `whose` names.
[[noreturn]] void refuse_empty_box(const Command& c, int level, std::span<const dtm::GridPoint> points,
                                   const dtm::Grid& grid, const char* whose) {
  dtm::InputPoint lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const dtm::GridPoint& g : points) {
    const dtm::InputPoint p = grid.to_input(g);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  char text[400];
  std::snprintf(text, sizeof text, "--box %g %g %g %g %g %g: no tetrahedron of level %d meets the box",
                c.box[0], c.box[1], c.box[2], c.box[3], c.box[4], c.box[5], level);
  std::string why = text;
  if (!points.empty()) {
    std::snprintf(text, sizeof text, " (%s span %g %g %g to %g %g %g)", whose, lo.x, lo.y, lo.z, hi.x, hi.y,
                  hi.z);
    why += text;
  }
  throw std::runtime_error(c.input + ": " + why);
}

// --box: the region's cells, from the chunks it needs.
int run_region(const Command& c, dtm::MeshFormat format) {
  if (c.input == "-") throw dtm::UsageError("--box reads the stream by offset: give a file, not '-'");
  if (c.verify) throw dtm::UsageError("--box and --verify: verify the whole stream instead");
  auto source = dtm::FileSource::open(c.input);
  if (!source.ok()) throw std::runtime_error(source.status().message());
  std::vector<uint8_t> head(dtm::kHeaderSize);
  dtm::StreamHeader header;
  if (source->size() < head.size() || !source->read(0, head).ok() || !dtm::parse_header(head, header).ok())
    header = {};  // decode_region says what is wrong
  const std::array<double, 3> lo = {c.box[0], c.box[1], c.box[2]}, hi = {c.box[3], c.box[4], c.box[5]};
  for (double v : c.box)
    if (!std::isfinite(v)) throw dtm::UsageError("--box: each corner's coordinates must be finite numbers");
  if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2])
    throw dtm::UsageError("--box: each of X0 Y0 Z0 must be at most X1 Y1 Z1");
  dtm::DecoderOptions options;
  options.max_vertices = c.max_vertices;
  if (header.level_count > 0 && !(header.flags & dtm::kFlagBricks)) {
    // Not bricked: the level is decoded whole, as meshdec writes it, and
    // the box cut from it with all it carries (tagged faces, cell data,
    // `boundary`).
    dtm::PhaseDisplay display(!c.quiet && isatty(STDERR_FILENO), c.verbose && !c.quiet);
    options.stop_after_level = c.level;
    options.on_phase = [&](std::string_view phase) { display.start(phase); };
    dtm::ProgressiveDecoder decoder(options);
    Verifier verifier;
    decode(c, decoder, verifier, display);
    const dtm::OutputMesh mesh =
        dtm::cut_to_box(dtm::decoded_mesh(decoder, c.input, dtm::numbers_edge_nodes(decoder)), lo, hi,
                        dtm::in_input_numbering(decoder));
    if (mesh.cells.empty())
      refuse_empty_box(c, decoder.finest_level(), decoder.points(), header.grid, "its vertices");
    if (decoder.has_edge_nodes() && !c.quiet)
      std::fprintf(
          stderr,
          "meshdec: the nodes on level 0's edges (a second-order mesh's) are not written: a box holds "
          "the linear cells\n");
    display.start("writing " + c.output);
    write_output(c, mesh, format);
    display.finish();
    if (!c.quiet)
      std::fprintf(
          stderr,
          "meshdec: level %d, box: %zu vertices, %zu tetrahedra (not a bricked stream: decoded whole)\n",
          decoder.finest_level(), mesh.points.size(), mesh.cells.size());
    return 0;
  }
  const dtm::GridBox box = dtm::grid_box_of(header.grid, lo, hi);
  const auto [level, region] = of_finest_whole_level(
      c, header.level_count, [&](int l) { return dtm::decode_region(*source, box, l, options); });
  if (!region.ok()) throw std::runtime_error(c.input + ": " + region.status().message());
  const dtm::OutputMesh mesh = dtm::region_output(*region, header.grid);
  if (mesh.cells.empty()) {
    // (Only the chunks near the box were read: the coarsest level, read
    // whole, says where the mesh is, within the levels' D_max.)
    const dtm::GridBox everything{{INT32_MIN, INT32_MIN, INT32_MIN}, {INT32_MAX, INT32_MAX, INT32_MAX}};
    const auto coarsest = dtm::decode_region(*source, everything, header.level_count - 1, options);
    refuse_empty_box(c, level, coarsest.ok() ? coarsest->points : std::vector<dtm::GridPoint>{}, header.grid,
                     "the coarsest level's vertices");
  }
  write_output(c, mesh, format);
  if (!c.quiet)
    std::fprintf(stderr,
                 "meshdec: level %d, box: %zu vertices, %zu tetrahedra; read %llu of %llu bytes (%.1f%%), "
                 "%llu chunks%s\n",
                 level, mesh.points.size(), mesh.cells.size(),
                 static_cast<unsigned long long>(region->bytes_read),
                 static_cast<unsigned long long>(source->size()),
                 100.0 * static_cast<double>(region->bytes_read) /
                     static_cast<double>(std::max<uint64_t>(1, source->size())),
                 static_cast<unsigned long long>(region->chunks_read),
                 region->bricked ? "" : " (not a bricked stream: decoded whole)");
  return 0;
}

int run(const Command& c) {
  const dtm::ThreadBudget threads(c.threads, dtm::mpi_session().cores_share());
  if (const std::string note = dtm::threads_held_note(c.threads);
      !note.empty() && !c.quiet && dtm::mpi_session().rank() == 0)
    std::fprintf(stderr, "meshdec: %s\n", note.c_str());
  // An output that cannot be written is said now, not after the decoding
  // (under mpirun by every rank, whose pieces go beside it, and said once).
  dtm::MpiSession& mpi = dtm::mpi_session();
  std::string problem;
  try {
    if (!c.output.empty() && c.output != "-") dtm::check_writable(c.output, {c.input});
  } catch (const std::invalid_argument& e) {
    problem = e.what();
  }
  if (mpi.size() > 1) {
    for (const auto& p : mpi.all_gather({reinterpret_cast<const uint8_t*>(problem.data()), problem.size()}))
      if (!p.empty()) throw dtm::AgreedError(std::string(p.begin(), p.end()), mpi.rank() == 0);
  } else if (!problem.empty()) {
    throw std::invalid_argument(problem);
  }
  if (dtm::lower_extension(c.output) == ".pvtu") return run_pieces(c);
  // (Each rank would decode the same level and write the same file.)
  if (mpi.size() > 1 && !c.output.empty())
    throw dtm::UsageError("under mpirun, meshdec writes a level in pieces, one a rank: -o X.pvtu",
                          mpi.rank() == 0);
  if (c.pieces > 0) throw dtm::UsageError("--pieces writes a .pvtu: -o X.pvtu");
  const dtm::MeshFormat format = output_format(c);
  // An option the output does not use is said, not silently dropped.
  const bool gltf = format == dtm::MeshFormat::kGlb || format == dtm::MeshFormat::kGltf;
  if (!c.quiet && c.colour_given && !gltf && format != dtm::MeshFormat::kDrc)
    std::fprintf(stderr, "meshdec: --color: only glTF and .drc outputs carry vertex colours; %s has none\n",
                 c.output.empty() ? "the output" : c.output.c_str());
  if (!c.quiet && c.no_draco && !gltf)
    std::fprintf(stderr,
                 "meshdec: --no-draco: only a glTF output can be Draco-compressed or not; %s is as it is\n",
                 c.output.empty() ? "the output" : c.output.c_str());
  if (!c.box.empty()) return run_region(c, format);
  // What the work is doing, on standard error: a status line on a terminal,
  // each phase's time with --verbose (the insertions, the carving, the exact
  // cells and the writing are most of a large level's).
  dtm::PhaseDisplay display(!c.quiet && isatty(STDERR_FILENO), c.verbose && !c.quiet);
  dtm::DecoderOptions options;
  options.max_vertices = c.max_vertices;
  options.stop_after_level = c.level;
  options.on_phase = [&](std::string_view phase) { display.start(phase); };
  dtm::ProgressiveDecoder decoder(options);
  Verifier verifier;
  decode(c, decoder, verifier, display);
  const dtm::OutputMesh mesh = dtm::decoded_mesh(decoder, c.input, dtm::writes_edge_nodes(format));
  // (Level 0 of a second-order input's exact stream, in a format of linear
  // cells: said.)
  if (decoder.has_edge_nodes() && !dtm::writes_edge_nodes(format) && !c.quiet)
    std::fprintf(
        stderr,
        "meshdec: the nodes on level 0's edges (a second-order mesh's) are not written: meshdec writes "
        "this format's linear cells (.vtu, .vtk, .msh, .inp and .e hold 10-node tetrahedra)\n");
  // The input's numbering and node ids (--keep-order) are level 0's: a
  // coarser level's nodes are numbered in its own order; and a format of
  // linear cells has no ids for a second-order mesh's nodes (the vertices
  // are still in the input's order among themselves).
  const uint32_t flags = decoder.header().flags;
  if (!c.quiet && (flags & (dtm::kFlagVertexOrder | dtm::kFlagNodeLabels)) && decoder.finest_level() > 0)
    std::fprintf(stderr,
                 "meshdec: %s: level %d is numbered in its own order: the input's node numbers%s are level "
                 "0's\n",
                 c.output.c_str(), decoder.finest_level(), flags & dtm::kFlagNodeLabels ? " and ids" : "");
  // (21.0: the input numbered its edge nodes among the corners; without
  // them the corners are numbered among themselves, 0 to n - 1.)
  if (!c.quiet && !(flags & dtm::kFlagNodeLabels) && decoder.finest_level() == 0 &&
      dtm::numbers_edge_nodes(decoder) && !dtm::writes_edge_nodes(format))
    std::fprintf(
        stderr,
        "meshdec: %s: not written: the input's node numbers (its edge nodes were numbered among the "
        "corners, which are numbered among themselves here: .msh, .vtu, .vtk, .inp and .e keep them)\n",
        c.output.c_str());
  // Level 0's cell arrays: a coarser level has other cells.
  if (!c.quiet && decoder.finest_level() > 0 && !decoder.cell_field_table().empty()) {
    std::string names;
    for (const dtm::FieldDescription& f : decoder.cell_field_table())
      names += (names.empty() ? "'" : ", '") + f.name + "'";
    std::fprintf(stderr,
                 "meshdec: %s: not written: the cell arrays %s (level 0's cells carry them; level %d has "
                 "cells of its own)\n",
                 c.output.c_str(), names.c_str(), decoder.finest_level());
  }
  if (!c.quiet && (flags & dtm::kFlagNodeLabels) && decoder.finest_level() == 0 && mesh.node_labels.empty())
    std::fprintf(stderr,
                 "meshdec: %s: not written: the input's node ids (a second-order mesh's: .msh, .inp and .e "
                 "number its nodes with them)\n",
                 c.output.c_str());
  display.start("writing " + c.output);
  write_output(c, mesh, format);
  display.finish();
  if (!c.quiet) {
    std::string note = c.verify ? ", verified " + std::to_string(verifier.verified()) + " levels" : "";
    const bool draco = format == dtm::MeshFormat::kDrc ||
                       ((format == dtm::MeshFormat::kGlb || format == dtm::MeshFormat::kGltf) && !c.no_draco);
    if (format == dtm::MeshFormat::kPly || format == dtm::MeshFormat::kOff ||
        format == dtm::MeshFormat::kGlb || format == dtm::MeshFormat::kGltf ||
        format == dtm::MeshFormat::kDrc) {
      const dtm::BoundarySurface s = dtm::boundary_surface(mesh);
      if (dtm::draws_regions(mesh, format, c.style)) {
        const dtm::BoundarySurface r = dtm::region_surfaces(mesh).surface;
        note += "; the regions' surfaces: " + std::to_string(r.vertices.size()) + " vertices, " +
                std::to_string(r.triangles.size()) + " triangles";
      } else {
        note += "; boundary surface: " + std::to_string(s.vertices.size()) + " vertices, " +
                std::to_string(s.triangles.size()) + " triangles";
      }
      if (draco) {
        // The quantization Draco was given, and what it costs the positions.
        // (float32 positions add their rounding: a .drc holds them whole,
        // a glTF file from its node's translation.)
        const dtm::SurfaceQuantization q = dtm::surface_quantization(mesh, s, format);
        char text[320];
        std::snprintf(
            text, sizeof text,
            "; Draco: positions %d bits (step %.6g, the stream's grid %.6g: within %.6g of the "
            "decoded positions%s), normals %d bits, colours %d bits",
            q.position_bits, q.draco_step, q.grid_step, q.draco_step / 2 + q.float_error,
            q.float_error > q.grid_step / 2 ? ", float32 so far from the origin rounding the most" : "",
            dtm::kNormalBits, dtm::kColourBits);
        note += text;
      }
    }
    if (mesh.edge_nodes > 0) note = ", " + std::to_string(mesh.edge_nodes) + " nodes on their edges" + note;
    std::fprintf(stderr, "meshdec: level %d: %zu vertices, %zu tetrahedra%s\n", decoder.finest_level(),
                 mesh.points.size() - mesh.edge_nodes, mesh.cells.size(), note.c_str());
  }
  return 0;
}

}  // namespace

namespace dtm {
MpiSession* the_session = nullptr;
MpiSession& mpi_session() { return *the_session; }
}  // namespace dtm

int main(int argc, char** argv) {
  dtm::ask_for_huge_pages(argv);  // before MPI and any thread: it may start the tool again
  dtm::MpiSession mpi(&argc, &argv);
  dtm::the_session = &mpi;
  dtm::tool_rank() = mpi.rank();
  if (!dtm::ranks_run_the_same_command(mpi, "meshdec", argc, argv)) return 2;
  return dtm::tool_main<Command>("meshdec", "decode a .dtm stream to a tetrahedral mesh", kExamples, argc,
                                 argv, add_options, run);
}
