#include "nrrd.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include "format_error.h"
#include "text_cursor.h"

namespace dtm {
namespace {

std::optional<ScalarType> nrrd_type(const std::string& name) {
  static const std::map<std::string, ScalarType> kTypes = {{"signed char", ScalarType::kInt8},
                                                           {"int8", ScalarType::kInt8},
                                                           {"int8_t", ScalarType::kInt8},
                                                           {"uchar", ScalarType::kUInt8},
                                                           {"unsigned char", ScalarType::kUInt8},
                                                           {"uint8", ScalarType::kUInt8},
                                                           {"uint8_t", ScalarType::kUInt8},
                                                           {"short", ScalarType::kInt16},
                                                           {"short int", ScalarType::kInt16},
                                                           {"signed short", ScalarType::kInt16},
                                                           {"signed short int", ScalarType::kInt16},
                                                           {"int16", ScalarType::kInt16},
                                                           {"int16_t", ScalarType::kInt16},
                                                           {"ushort", ScalarType::kUInt16},
                                                           {"unsigned short", ScalarType::kUInt16},
                                                           {"unsigned short int", ScalarType::kUInt16},
                                                           {"uint16", ScalarType::kUInt16},
                                                           {"uint16_t", ScalarType::kUInt16},
                                                           {"int", ScalarType::kInt32},
                                                           {"signed int", ScalarType::kInt32},
                                                           {"int32", ScalarType::kInt32},
                                                           {"int32_t", ScalarType::kInt32},
                                                           {"uint", ScalarType::kUInt32},
                                                           {"unsigned int", ScalarType::kUInt32},
                                                           {"uint32", ScalarType::kUInt32},
                                                           {"uint32_t", ScalarType::kUInt32},
                                                           {"float", ScalarType::kFloat32},
                                                           {"double", ScalarType::kFloat64}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) return std::nullopt;
  return it->second;
}

// Fields that do not change where voxels are or what they hold.
bool is_descriptive(const std::string& field) {
  static const char* kFields[] = {"content",     "kinds",        "centers",     "centerings",
                                  "labels",      "units",        "space units", "measurement frame",
                                  "min",         "max",          "old min",     "old max",
                                  "thicknesses", "axis mins",    "axismins",    "axis maxs",
                                  "axismaxs",    "sample units", "sampleunits", "number",
                                  "block size",  "blocksize",    "space",       "space dimension"};
  for (const char* f : kFields)
    if (field == f) return true;
  return false;
}

std::string trim(std::string_view s) {
  const size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string_view::npos ? "" : std::string(s.substr(b, e - b + 1));
}

}  // namespace

// Inflates in 1 MiB steps, so that memory follows the data actually present
// rather than the size the header claims (a few bytes of gzip can claim a
// 2^33-voxel volume).
std::string gunzip(std::string_view compressed, uint64_t expected, const std::string& path) {
  std::string out;
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK)
    throw FormatError(path + ": cannot start zlib");  // gzip or zlib header
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
  z.avail_in = static_cast<uInt>(compressed.size());
  constexpr uint64_t kStep = uint64_t{1} << 20;
  int r = Z_OK;
  while (r == Z_OK) {
    const uint64_t have = out.size();
    const uint64_t room = std::min(kStep, expected + 1 - have);  // one byte more: detects excess data
    if (room == 0) break;
    out.resize(have + room);
    z.next_out = reinterpret_cast<Bytef*>(out.data() + have);
    z.avail_out = static_cast<uInt>(room);
    r = inflate(&z, Z_NO_FLUSH);
    out.resize(have + room - z.avail_out);
    if (r == Z_BUF_ERROR && z.avail_in == 0) break;  // input exhausted before the end of the stream
  }
  const uint64_t produced = out.size();
  inflateEnd(&z);
  if (produced > expected)
    throw FormatError(path + ": gzip data holds more than the " + std::to_string(expected) +
                      " bytes of the volume");
  if (r != Z_STREAM_END)
    throw FormatError(path + ": gzip data is damaged or truncated (" + std::to_string(produced) + " of " +
                      std::to_string(expected) + " bytes)" + (z.msg ? std::string(": ") + z.msg : ""));
  if (produced != expected)
    throw FormatError(path + ": gzip data holds " + std::to_string(produced) + " bytes, the volume needs " +
                      std::to_string(expected));
  return out;
}

namespace {

// The header's fields, read up to the blank line (or the file's end).
class NrrdHeader {
 public:
  NrrdHeader(TextCursor& c, const std::string& path) : path_(path) {
    if (c.remaining() == 0) c.fail("empty file, expected a 'NRRD000X' magic line");
    const std::string magic(c.rest_of_line());
    if (magic.size() != 8 || magic.substr(0, 7) != "NRRD000" || magic[7] < '1' || magic[7] > '5')
      c.fail("not a NRRD file (expected 'NRRD0001' to 'NRRD0005', found '" + magic.substr(0, 20) + "')");
    while (c.remaining() > 0) {
      const std::string_view line = c.rest_of_line();
      if (line.empty()) {
        blank_line_ = true;
        break;
      }
      add(c, line);
    }
  }

  const std::string& path() const { return path_; }
  bool blank_line() const { return blank_line_; }
  const std::string* field(const char* key) const {
    const auto it = fields_.find(key);
    return it == fields_.end() ? nullptr : &it->second;
  }
  const std::string& require(const char* key) const {
    const std::string* v = field(key);
    if (!v) fail("header has no '" + std::string(key) + "' field");
    return *v;
  }
  // The numbers of a field's value, separated by blanks, commas or parentheses.
  std::vector<double> numbers(const std::string& text, const char* key) const {
    std::vector<double> out;
    std::string_view s = text;
    while (true) {
      const size_t b = s.find_first_not_of(" \t(),");
      if (b == std::string_view::npos) break;
      s.remove_prefix(b);
      const size_t e = std::min(s.find_first_of(" \t(),"), s.size());
      double v = 0;
      const auto [end, ec] = std::from_chars(s.data(), s.data() + e, v);
      if (ec != std::errc() || end != s.data() + e || !std::isfinite(v))
        fail("field '" + std::string(key) + "': expected numbers, found '" + std::string(s.substr(0, e)) +
             "'");
      out.push_back(v);
      s.remove_prefix(e);
    }
    return out;
  }
  // The numbers of an optional field, which must hold `count` of them.
  std::optional<std::vector<double>> vector(const char* key, size_t count, const char* what) const {
    const std::string* text = field(key);
    if (!text) return std::nullopt;
    auto values = numbers(*text, key);
    if (values.size() != count) fail("'" + std::string(key) + "' must " + what);
    return values;
  }
  [[noreturn]] void fail(const std::string& what) const { throw FormatError(path_ + ": " + what); }

 private:
  void add(TextCursor& c, std::string_view line) {
    if (line[0] == '#') return;
    if (line.find(":=") != std::string_view::npos && line.find(":=") < line.find(": "))
      return;  // key/value pair
    const size_t colon = line.find(": ");
    if (colon == std::string_view::npos) c.fail("expected 'field: value', found '" + std::string(line) + "'");
    static const std::map<std::string, std::string> kSpellings = {{"datafile", "data file"},
                                                                  {"byteskip", "byte skip"},
                                                                  {"lineskip", "line skip"},
                                                                  {"spacedirections", "space directions"},
                                                                  {"spaceorigin", "space origin"}};
    std::string key(line.substr(0, colon));
    if (const auto it = kSpellings.find(key); it != kSpellings.end()) key = it->second;
    if (!fields_.emplace(key, trim(line.substr(colon + 2))).second) c.fail("field '" + key + "' given twice");
    static const char* kUsed[] = {"type",         "dimension", "sizes",  "spacings",  "space directions",
                                  "space origin", "encoding",  "endian", "data file", "byte skip",
                                  "line skip"};
    if (std::find_if(std::begin(kUsed), std::end(kUsed), [&](const char* f) { return key == f; }) ==
            std::end(kUsed) &&
        !is_descriptive(key))
      c.fail("unknown field '" + key + "'");
  }

  std::string path_;
  std::map<std::string, std::string> fields_;
  bool blank_line_ = false;
};

// Type, sizes, placement in space and byte order: everything but the data.
Volume volume_layout(const NrrdHeader& h) {
  Volume v;
  const auto type = nrrd_type(h.require("type"));
  if (!type) h.fail("unsupported type '" + h.require("type") + "'");
  v.type = *type;
  if (h.require("dimension") != "3")
    h.fail("dimension must be 3 (one scalar per voxel), got " + h.require("dimension"));
  const auto sizes = h.numbers(h.require("sizes"), "sizes");
  if (sizes.size() != 3) h.fail("'sizes' must hold 3 values");
  for (int a = 0; a < 3; ++a) {
    if (sizes[a] < 1 || sizes[a] > (1 << 24) || sizes[a] != std::floor(sizes[a]))
      h.fail("bad size " + std::to_string(sizes[a]));
    v.sizes[a] = static_cast<uint64_t>(sizes[a]);
  }
  if (v.voxels() > (uint64_t{1} << 33))
    h.fail(std::to_string(v.voxels()) + " voxels: larger than this reader handles (2^33)");
  if (const auto d = h.vector("space directions", 9, "be three 3-vectors")) {
    for (int a = 0; a < 3; ++a) v.directions[a] = {(*d)[3 * a], (*d)[3 * a + 1], (*d)[3 * a + 2]};
    if (h.field("spacings")) h.fail("both 'spacings' and 'space directions'");
  } else if (const auto s = h.vector("spacings", 3, "hold 3 values")) {
    for (int a = 0; a < 3; ++a)
      v.directions[a] = {a == 0 ? (*s)[0] : 0, a == 1 ? (*s)[1] : 0, a == 2 ? (*s)[2] : 0};
  }
  if (const auto o = h.vector("space origin", 3, "be a 3-vector")) v.origin = {(*o)[0], (*o)[1], (*o)[2]};
  const std::string& encoding = h.require("encoding");
  if (const std::string* e = h.field("endian")) {
    if (*e != "little" && *e != "big") h.fail("endian must be 'little' or 'big'");
    v.big_endian = *e == "big";
  } else if (scalar_size(v.type) > 1 && encoding != "ascii" && encoding != "text" && encoding != "txt") {
    h.fail("header has no 'endian' field");
  }
  return v;
}

// The encoded data: after the blank line or in the detached file (read into
// `detached`, its path into `data_path`), past the lines and bytes to skip.
std::string_view data_bytes(const NrrdHeader& h, TextCursor& c, uint64_t bytes, std::string& detached,
                            std::string& data_path) {
  std::string_view data;
  data_path = h.path();
  if (const std::string* file = h.field("data file")) {
    if (file->find(' ') != std::string::npos || *file == "LIST") h.fail("unsupported: a list of data files");
    const std::filesystem::path p(*file);
    data_path = p.is_absolute() ? p.string() : (std::filesystem::path(h.path()).parent_path() / p).string();
    try {
      detached = read_whole_file(data_path);
    } catch (const FormatError& e) {
      h.fail("data file: " + std::string(e.what()));
    }
    data = detached;
  } else {
    if (!h.blank_line()) h.fail("header ends without the blank line before the data");
    data = c.rest();
  }
  if (const auto n = h.vector("line skip", 1, "be one number")) {
    if ((*n)[0] < 0) h.fail("bad 'line skip'");
    for (int i = 0; i < (*n)[0]; ++i) {
      const size_t nl = data.find('\n');
      if (nl == std::string_view::npos) throw FormatError(data_path + ": ends within the lines to skip");
      data.remove_prefix(nl + 1);
    }
  }
  if (const auto n = h.vector("byte skip", 1, "be one number")) {
    if ((*n)[0] < -1) h.fail("bad 'byte skip'");
    if ((*n)[0] == -1) {
      if (h.require("encoding") != "raw") h.fail("'byte skip: -1' needs raw encoding");
      if (data.size() < bytes)
        throw FormatError(data_path + ": holds " + std::to_string(data.size()) + " bytes, the volume needs " +
                          std::to_string(bytes));
      data.remove_prefix(data.size() - bytes);
    } else {
      if ((*n)[0] > data.size()) throw FormatError(data_path + ": shorter than 'byte skip'");
      data.remove_prefix(static_cast<size_t>((*n)[0]));
    }
  }
  return data;
}

// ASCII data: every value as a little-endian float64.
std::string ascii_values(std::string_view data, const std::string& data_path, uint64_t voxels) {
  TextCursor t(data_path, std::string(data));
  // Each value takes a character and a separator at least.
  if (voxels > data.size() / 2 + 1)
    t.fail("data ends: " + std::to_string(data.size()) + " bytes of text cannot hold " +
           std::to_string(voxels) + " values");
  std::string out;
  out.reserve(voxels * 8);
  for (uint64_t i = 0; i < voxels; ++i) {
    if (t.at_end())
      t.fail("data ends after " + std::to_string(i) + " of " + std::to_string(voxels) + " values");
    const auto u = std::bit_cast<uint64_t>(t.number<double>("a value"));
    for (int k = 0; k < 8; ++k) out += static_cast<char>((u >> (8 * k)) & 0xff);
  }
  if (!t.at_end()) t.fail("more values than the volume's " + std::to_string(voxels));
  return out;
}

}  // namespace

Volume read_nrrd(const std::string& path) {
  TextCursor c = TextCursor::open(path);
  const NrrdHeader header(c, path);
  Volume v = volume_layout(header);
  const uint64_t bytes = v.voxels() * scalar_size(v.type);
  std::string detached, data_path;
  const std::string_view data = data_bytes(header, c, bytes, detached, data_path);
  const std::string& encoding = header.require("encoding");
  if (encoding == "raw") {
    if (data.size() != bytes)
      throw FormatError(data_path + ": " + std::string(data.size() < bytes ? "truncated: " : "") + "holds " +
                        std::to_string(data.size()) + " bytes of data, the " + std::to_string(v.sizes[0]) +
                        "x" + std::to_string(v.sizes[1]) + "x" + std::to_string(v.sizes[2]) +
                        " volume needs " + std::to_string(bytes));
    v.data.assign(data);
  } else if (encoding == "gzip" || encoding == "gz") {
    v.data = gunzip(data, bytes, data_path);
  } else if (encoding == "ascii" || encoding == "text" || encoding == "txt") {
    v.data = ascii_values(data, data_path, v.voxels());
    v.big_endian = false;
    v.type = ScalarType::kFloat64;
  } else {
    header.fail("unsupported encoding '" + encoding + "' (raw, gzip and ascii are read)");
  }
  return v;
}

}  // namespace dtm
