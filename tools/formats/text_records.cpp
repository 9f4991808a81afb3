#include "text_records.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string_view>

#include "common/parallel_for.h"
#include "tools/formats/files_read.h"
#include "tools/formats/text_cursor.h"

namespace dtm {
namespace {

constexpr size_t kPieceBytes = size_t{1} << 20;  // a thread's share of a block at a time

// Field separators: blanks, and commas as TetGen reads them.
bool separator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == ','; }

// A line's fields, up to its '#': false if it has none. (A character
// test, not string_view::find_first_of, which searches the set for each
// character: half the time of reading a large .ele.)
bool split(std::string_view line, TextRecords::Fields& fields) {
  fields.clear();
  const char* p = line.data();
  const char* const end = p + line.size();
  while (p != end && *p != '#') {
    if (separator(*p)) {
      ++p;
      continue;
    }
    const char* const first = p;
    while (p != end && !separator(*p) && *p != '#') ++p;
    fields.emplace_back(first, static_cast<size_t>(p - first));
  }
  return !fields.empty();
}

bool meaningful(std::string_view line) {
  for (const char c : line) {
    if (c == '#') return false;
    if (!separator(c)) return true;
  }
  return false;
}

// The line starting at `at` (without its '\n') and where the next one starts.
std::string_view line_at(std::string_view text, size_t at, size_t& next) {
  const size_t end = text.find('\n', at);
  next = end == std::string_view::npos ? text.size() : end + 1;
  return text.substr(at, (end == std::string_view::npos ? text.size() : end) - at);
}

constexpr size_t kScanBytes = size_t{1} << 20;

// The first line start at or after `at` (> 0): the byte after the first
// '\n' at or after at - 1, or the file's end.
uint64_t next_line_start(const std::string& path, uint64_t at) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(at - 1));
  std::vector<char> buffer(4096);  // a line is most often far shorter
  uint64_t offset = at - 1;
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto got = static_cast<size_t>(in.gcount());
    if (const void* end = std::memchr(buffer.data(), '\n', got))
      return offset + static_cast<uint64_t>(static_cast<const char*>(end) - buffer.data()) + 1;
    offset += got;
  }
  return offset;
}

// The lines that end before byte `end`.
uint64_t lines_before(const std::string& path, uint64_t end) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> buffer(kScanBytes);
  uint64_t lines = 0;
  for (uint64_t offset = 0; offset < end && in;) {
    in.read(buffer.data(), static_cast<std::streamsize>(std::min<uint64_t>(buffer.size(), end - offset)));
    const auto got = static_cast<size_t>(in.gcount());
    lines += static_cast<uint64_t>(std::count(buffer.data(), buffer.data() + got, '\n'));
    offset += got;
  }
  return lines;
}

}  // namespace

TextRecords::TextRecords(const std::string& path, size_t block_bytes)
    : path_(path), in_(path, std::ios::binary), block_bytes_(std::max<size_t>(block_bytes, 1)) {
  if (!in_) throw FormatError(path + ": cannot open file");
  note_file_read(path);
  // (A byte-order mark, as Windows editors write one, is not a record's.)
  skip_byte_order_mark(in_);
  read_ = static_cast<uint64_t>(in_.tellg());
  // A small file in one small block (a block is allocated whole).
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (!error) block_bytes_ = std::min<size_t>(block_bytes_, std::max<uintmax_t>(size + 1, 64));
}

void TextRecords::fail(size_t line, const std::string& problem) const {
  if (skipped_.second > skipped_.first)
    line += lines_before(path_, skipped_.second) - lines_before(path_, skipped_.first);
  throw FormatError(path_ + ":" + std::to_string(line) + ": " + problem);
}

bool TextRecords::read_block() {
  // The line begun at the end of the last block starts this one, in the
  // buffer the blocks share: swapping in the carry's buffer instead made
  // every block grow a fresh one, whose new pages (32 MB a block) were then
  // faulted on this thread while the parsing threads waited.
  text_.assign(carry_);
  carry_.clear();
  at_ = 0;
  if (eof_) return !text_.empty();
  // Whole lines: up to the last line end read, the rest carried over (a
  // line longer than a block grows the block until it ends).
  while (true) {
    const size_t had = text_.size();
    const auto want = static_cast<size_t>(std::min<uint64_t>(block_bytes_, left_));
    text_.resize(had + want);
    in_.read(text_.data() + had, static_cast<std::streamsize>(want));
    const auto got = static_cast<size_t>(in_.gcount());
    text_.resize(had + got);
    read_ += got;
    left_ -= std::min<uint64_t>(left_, got);
    if (!in_ || left_ == 0) {
      eof_ = true;
      return !text_.empty();
    }
    const size_t last = text_.rfind('\n');
    if (last != std::string::npos && last >= had) {
      carry_.assign(text_, last + 1);
      text_.resize(last + 1);
      return true;
    }
  }
}

void TextRecords::keep_to_part(int part, int parts) {
  if (parts <= 1) return;
  // Where the records begin: what next() has not yet taken.
  const uint64_t from = read_ - carry_.size() - (text_.size() - at_);
  std::error_code error;
  const uint64_t size = std::filesystem::file_size(path_, error);
  if (error) throw FormatError(path_ + ": cannot tell the file's size");
  const uint64_t span = size - from;
  const auto cut = [&](int p) {
    const uint64_t at = from + static_cast<uint64_t>(static_cast<unsigned __int128>(span) *
                                                     static_cast<unsigned>(p) / static_cast<unsigned>(parts));
    return at == from ? from : next_line_start(path_, at);
  };
  const uint64_t first = cut(part), last = part + 1 == parts ? size : cut(part + 1);
  // The lines of the parts before this one are counted only for a message
  // (fail()): the last part's count would read almost the whole file.
  skipped_ = {from, first};
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(first));
  read_ = first;
  left_ = last - first;
  text_.clear();
  carry_.clear();
  at_ = 0;
  eof_ = left_ == 0;
}

bool TextRecords::next(Fields& fields) {
  while (true) {
    if (at_ >= text_.size() && !read_block()) return false;
    size_t next = 0;
    const std::string_view line = line_at(text_, at_, next);
    at_ = next;
    ++line_;
    if (split(line, fields)) return true;
  }
}

TextRecords::Found TextRecords::records(uint64_t count, const std::function<void(size_t, size_t)>& start,
                                        const std::function<void(size_t, size_t, const Fields&)>& parse,
                                        const std::function<void()>& finish) {
  Found found;
  while (at_ < text_.size() || read_block()) {
    // The block's pieces, cut at line ends.
    const std::string_view text(text_);
    std::vector<size_t> cut = {at_};
    while (cut.back() < text.size()) {
      const size_t end = text.find('\n', cut.back() + kPieceBytes);
      cut.push_back(end == std::string_view::npos ? text.size() : end + 1);
    }
    const size_t pieces = cut.size() - 1;
    // Per piece, its lines and meaningful ones; from them, where each
    // piece's records and lines begin.
    std::vector<size_t> lines(pieces + 1, 0), records(pieces + 1, 0);
    parallel_for(pieces, [&](size_t p) {
      for (size_t at = cut[p], next = 0; at < cut[p + 1]; at = next) {
        ++lines[p + 1];
        if (meaningful(line_at(text, at, next))) ++records[p + 1];
      }
    });
    for (size_t p = 0; p < pieces; ++p) lines[p + 1] += lines[p], records[p + 1] += records[p];
    // The records of this block that are wanted.
    const uint64_t wanted = std::min<uint64_t>(records[pieces], count - found.records);
    start(static_cast<size_t>(wanted), text.size() - cut.front());
    std::vector<std::exception_ptr> error(pieces);
    std::vector<size_t> extra(pieces, 0);
    parallel_for(pieces, [&](size_t p) {
      Fields fields;
      size_t record = records[p], line = line_ + lines[p];
      try {
        for (size_t at = cut[p], next = 0; at < cut[p + 1]; at = next) {
          ++line;
          if (!split(line_at(text, at, next), fields)) continue;
          if (record >= wanted) {
            extra[p] = line;
            return;
          }
          parse(record++, line, fields);
        }
      } catch (...) {
        error[p] = std::current_exception();
      }
    });
    for (size_t p = 0; p < pieces; ++p) {
      if (error[p]) std::rethrow_exception(error[p]);
      if (extra[p]) {
        found.extra_line = extra[p];
        break;
      }
    }
    finish();
    found.records += wanted;
    line_ += lines[pieces];
    at_ = text_.size();
    if (found.extra_line) break;
  }
  return found;
}

}  // namespace dtm
