// The netCDF classic header check (netcdf_header.h).
#include "netcdf_header.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "format_error.h"

namespace dtm {
namespace {

class Header {
 public:
  explicit Header(const std::string& path)
      : path_(path), in_(path, std::ios::binary), size_(std::filesystem::file_size(path)) {}

  void check() {
    char magic[4] = {};
    if (size_ < 4 || !in_.read(magic, 4) || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F') return;
    const int version = static_cast<unsigned char>(magic[3]);
    if (version != 1 && version != 2 && version != 5) return;  // (libnetcdf names it)
    at_ = 4;
    wide_ = version == 5;
    const int offset_bytes = version == 1 ? 4 : 8;
    const uint64_t records = count();
    // Dimensions: a name and a length each (0: the record dimension).
    std::vector<uint64_t> lengths;
    for (uint64_t n = list(0x0A, "dimensions"), i = 0; i < n; ++i) name(), lengths.push_back(count());
    attributes();
    // Variables: their data must be in the file too (libnetcdf reads what
    // is past its end as fill values, and would give a cut file's mesh
    // without a word). A record variable's data is one slab a record.
    struct Data {
      uint64_t begin = 0, bytes = 0;
      bool record = false;
    };
    std::vector<Data> data;
    const uint64_t variables = list(0x0B, "variables");
    for (uint64_t i = 0; i < variables; ++i) {
      name();
      const uint64_t dimensions = count();
      if (dimensions > (size_ - at_) / (wide_ ? 8 : 4)) fail("a variable's dimensions: too many");
      Data d;
      d.bytes = 1;
      for (uint64_t k = 0; k < dimensions; ++k) {
        const uint64_t dim = count();
        if (dim >= lengths.size())
          fail("a variable's dimension " + std::to_string(dim) + " of " + std::to_string(lengths.size()));
        if (lengths[dim] == 0 && k == 0) {
          d.record = true;
          continue;
        }
        if (lengths[dim] != 0 && d.bytes > size_ / lengths[dim]) fail("a variable's data past the end");
        d.bytes *= lengths[dim];
      }
      attributes();
      const uint64_t each = type_size(word());
      if (d.bytes > size_ / each) fail("a variable's data past the end");
      d.bytes *= each;
      count();  // vsize (the library's own rounding of the bytes above)
      d.begin = read(static_cast<size_t>(offset_bytes));
      data.push_back(d);
    }
    uint64_t record_bytes = 0, record_variables = 0;
    for (const Data& d : data)
      if (d.record) record_bytes += (d.bytes + 3) / 4 * 4, ++record_variables;
    if (record_variables == 1)
      for (const Data& d : data) record_bytes = d.record ? d.bytes : record_bytes;
    // (0xFFFFFFFF records: a file still being written, its count unknown.)
    const bool streaming = records == (wide_ ? UINT64_MAX : UINT32_MAX);
    for (const Data& d : data) {
      // (A record variable of a file without records yet holds no data.)
      if (d.record && (records == 0 || streaming)) continue;
      uint64_t end = size_ + 1;
      if (d.begin <= size_) {
        if (!d.record) {
          end = d.begin + d.bytes;
        } else if (record_bytes == 0 || records - 1 <= (size_ - d.begin) / record_bytes) {
          end = d.begin + (records - 1) * record_bytes + d.bytes;
        }
      }
      if (end > size_)
        throw FormatError(
            path_ + ": cut short: its netCDF header puts data " +
            (end > size_ + 1 ? "up to byte " + std::to_string(end) : std::string("past its end")) +
            ", the file has " + std::to_string(size_) + " bytes");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what, bool beyond_the_file = true) const {
    throw FormatError(path_ + ": byte " + std::to_string(at_) + ": " + what +
                      (beyond_the_file ? " (a netCDF header that claims more than the file holds)" : ""));
  }
  uint64_t word() { return read(4); }
  uint64_t count() { return read(wide_ ? 8 : 4); }
  uint64_t read(size_t n) {
    char b[8] = {};
    if (size_ - at_ < n || !in_.seekg(static_cast<std::streamoff>(at_)) ||
        !in_.read(b, static_cast<std::streamsize>(n)))
      fail("the header ends early");
    uint64_t v = 0;
    for (size_t k = 0; k < n; ++k) v = (v << 8) | static_cast<uint8_t>(b[k]);
    at_ += n;
    return v;
  }
  // `n` items of `size` bytes, padded to 4, within the file.
  void skip(uint64_t n, uint64_t size, const char* what) {
    const uint64_t left = size_ - at_;
    if (size != 0 && n > left / size) fail(std::string(what) + ": " + std::to_string(n) + " claimed");
    at_ += (n * size + 3) / 4 * 4;
    if (at_ > size_) fail(std::string(what) + " past the end");
  }
  // (libnetcdf copies a name into buffers of NC_MAX_NAME + 1 bytes, 257,
  // without looking at its length.)
  void name() {
    const uint64_t length = count();
    if (length > 256) fail("a name of " + std::to_string(length) + " bytes, more than netCDF's 256", false);
    skip(length, 1, "a name");
  }
  uint64_t list(uint64_t tag, const char* what) {
    const uint64_t t = word(), n = count();
    if (t == 0 && n == 0) return 0;
    if (t != tag) fail(std::string("not the list of ") + what);
    // (Each item takes 4 bytes at least.)
    if (n > (size_ - at_) / 4) fail(std::string(what) + ": " + std::to_string(n) + " claimed");
    return n;
  }
  uint64_t type_size(uint64_t type) {
    static constexpr std::array<uint64_t, 12> kSizes = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    if (type == 0 || type >= kSizes.size() || (!wide_ && type > 6)) fail("not a netCDF type");
    return kSizes[type];
  }
  void attributes() {
    for (uint64_t n = list(0x0C, "attributes"), i = 0; i < n; ++i) {
      name();
      const uint64_t size = type_size(word());
      skip(count(), size, "an attribute's values");
    }
  }

  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0, at_ = 0;
  bool wide_ = false;
};

}  // namespace

void check_netcdf_header(const std::string& path) { Header(path).check(); }

}  // namespace dtm
