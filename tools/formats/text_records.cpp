#include "text_records.h"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <string_view>

#include "common/parallel_for.h"

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

}  // namespace

TextRecords::TextRecords(const std::string& path, size_t block_bytes)
    : path_(path), in_(path, std::ios::binary), block_bytes_(std::max<size_t>(block_bytes, 1)) {
  if (!in_) throw FormatError(path + ": cannot open file");
  // A small file in one small block (a block is allocated whole).
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (!error) block_bytes_ = std::min<size_t>(block_bytes_, std::max<uintmax_t>(size + 1, 64));
}

void TextRecords::fail(size_t line, const std::string& problem) const {
  throw FormatError(path_ + ":" + std::to_string(line) + ": " + problem);
}

bool TextRecords::read_block() {
  text_.swap(carry_);
  carry_.clear();
  at_ = 0;
  if (eof_) return !text_.empty();
  // Whole lines: up to the last line end read, the rest carried over (a
  // line longer than a block grows the block until it ends).
  while (true) {
    const size_t had = text_.size();
    text_.resize(had + block_bytes_);
    in_.read(text_.data() + had, static_cast<std::streamsize>(block_bytes_));
    text_.resize(had + static_cast<size_t>(in_.gcount()));
    if (!in_) {
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
