#include "text_cursor.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/parallel_for.h"
#include "tools/formats/files_read.h"

namespace dtm {

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot open file");
  note_file_read(path);
  // A file of known size read into its string at once (a stream's copy
  // would hold it twice and copy it twice: 0.3 s at 350 MB).
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > 0 && std::filesystem::is_regular_file(path, ec) && !ec) {
    std::string bytes(size, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (static_cast<uint64_t>(in.gcount()) != size) throw FormatError(path + ": cannot read file");
    return bytes;
  }
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw FormatError(path + ": cannot read file");
  return std::move(s).str();
}

TextCursor::TextCursor(std::string path, std::string bytes, char comment)
    : path_(std::move(path)), data_(std::move(bytes)), comment_(comment) {
  if (data_.starts_with(kUtf8ByteOrderMark)) pos_ = kUtf8ByteOrderMark.size();
}

void TextCursor::skip_space() {
  while (pos_ < data_.size()) {
    const char c = data_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (comment_ != '\0' && c == comment_) {
      while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
    } else {
      return;
    }
  }
}

bool TextCursor::at_end() {
  skip_space();
  return pos_ >= data_.size();
}

std::string_view TextCursor::peek() {
  // Leaves the position alone: binary data may follow the current line.
  const size_t pos = pos_, line = line_;
  skip_space();
  size_t e = pos_;
  while (e < data_.size() && !std::isspace(static_cast<unsigned char>(data_[e]))) ++e;
  const std::string_view out = std::string_view(data_).substr(pos_, e - pos_);
  pos_ = pos;
  line_ = line;
  return out;
}

std::string_view TextCursor::token(const char* what) {
  skip_space();
  token_line_ = line_;
  token_offset_ = pos_;
  if (pos_ >= data_.size()) fail(std::string("file ends, expected ") + what);
  const size_t b = pos_;
  while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
  return std::string_view(data_).substr(b, pos_ - b);
}

std::string_view TextCursor::rest_of_line() {
  token_line_ = line_;
  token_offset_ = pos_;
  const size_t b = pos_;
  while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  size_t e = pos_;
  if (pos_ < data_.size()) {
    ++pos_;
    ++line_;
  }
  if (e > b && data_[e - 1] == '\r') --e;
  return std::string_view(data_).substr(b, e - b);
}

void TextCursor::skip_to_next_line() {
  while (pos_ < data_.size() && data_[pos_] != '\n') {
    if (!std::isspace(static_cast<unsigned char>(data_[pos_]))) {
      token_line_ = line_;
      token_offset_ = pos_;
      fail("unexpected '" + std::string(peek()) + "' at the end of the line");
    }
    ++pos_;
  }
  if (pos_ < data_.size()) {
    ++pos_;
    ++line_;
  }
}

void TextCursor::lines(uint64_t n, const std::function<void(uint64_t, std::string_view)>& parse) {
  // Pieces of this many lines, each parsed on one thread.
  constexpr uint64_t kPiece = 16384;
  lines_first_ = line_;
  token_line_ = line_;
  token_offset_ = pos_;
  const std::string_view all(data_);
  // The line from `at` (without '\r\n'); `at` moves past its end. Past the
  // end of the file, empty lines.
  const auto next_line = [&](size_t& at) {
    const size_t b = at;
    const void* nl = std::memchr(all.data() + b, '\n', all.size() - b);
    size_t e = nl ? static_cast<size_t>(static_cast<const char*>(nl) - all.data()) : all.size();
    at = nl ? e + 1 : all.size();
    if (e > b && all[e - 1] == '\r') --e;
    return all.substr(b, e - b);
  };
  // Where each piece starts, and where the lines end.
  std::vector<size_t> starts;
  size_t at = pos_;
  size_t ends = 0;  // line ends passed
  for (uint64_t i = 0; i < n; ++i) {
    if (i % kPiece == 0) starts.push_back(at);
    if (at == all.size()) break;  // the rest are empty
    next_line(at);
    ends += all[at - 1] == '\n';
  }
  if (starts.empty()) starts.push_back(at);
  const size_t pieces = (n + kPiece - 1) / kPiece;
  starts.resize(pieces, at);
  // Per piece: what its first failure threw.
  std::vector<std::exception_ptr> failure(pieces);
  const auto run = [&](size_t p) {
    size_t from = starts[p];
    const uint64_t first = p * kPiece, last = std::min<uint64_t>(n, first + kPiece);
    try {
      for (uint64_t i = first; i < last; ++i) parse(i, next_line(from));
    } catch (...) {
      failure[p] = std::current_exception();
    }
  };
  if (pieces < 2) {
    for (size_t p = 0; p < pieces; ++p) run(p);
  } else {
    parallel_for(pieces, run);
  }
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
  pos_ = at;
  line_ += ends;
}

bool TextCursor::tokens(uint64_t n, const std::function<bool(uint64_t, std::string_view)>& parse) {
  if (comment_ != '\0') return false;
  if (n == 0) return true;
  const Mark start = mark();
  skip_space();
  const std::string_view all(data_);
  const size_t size = all.size();
  // std::isspace in the C locale, without its call.
  const auto space = [&](size_t at) {
    const char c = all[at];
    return c == ' ' || (c >= '\t' && c <= '\r');
  };
  // Pieces of about a megabyte, each cut after a token, a batch of them at
  // a time until they hold n tokens; per piece, the tokens that start in it.
  constexpr size_t kPiece = size_t{1} << 20;
  std::vector<size_t> cut = {pos_};
  std::vector<uint64_t> first = {0};  // tokens before each piece
  // (A batch is many pieces: parallel_for runs its first alone.)
  const size_t batch = 16 * static_cast<size_t>(std::max(1, thread_count()));
  while (first.back() < n && cut.back() < size) {
    const size_t before = cut.size() - 1;
    for (size_t k = 0; k < batch && cut.back() < size; ++k) {
      size_t end = std::min(size, cut.back() + kPiece);
      while (end < size && !space(end)) ++end;
      cut.push_back(end);
    }
    const size_t pieces = cut.size() - 1 - before;
    std::vector<uint64_t> counts(pieces, 0);
    parallel_for(pieces, [&](size_t p) {
      uint64_t c = 0;
      for (size_t at = cut[before + p], end = cut[before + p + 1]; at < end; ++at)
        c += !space(at) && (at == cut[before + p] || space(at - 1));
      counts[p] = c;
    });
    for (uint64_t c : counts) first.push_back(first.back() + c);
  }
  if (first.back() < n) {
    restore(start);
    return false;
  }
  // Parse each piece's tokens (up to the n-th), and count its line ends up
  // to where the n-th token ends.
  const size_t pieces = cut.size() - 1;
  std::vector<uint8_t> refused(pieces, 0);
  std::vector<size_t> ends(pieces, 0), stop(pieces, 0);
  parallel_for(pieces, [&](size_t p) {
    if (first[p] >= n) return;
    uint64_t i = first[p];
    size_t at = cut[p];
    const size_t end = cut[p + 1];
    while (at < end && i < n) {
      if (space(at)) {
        ends[p] += all[at] == '\n';
        ++at;
        continue;
      }
      const size_t b = at;
      while (at < size && !space(at)) ++at;
      if (!parse(i++, all.substr(b, at - b))) {
        refused[p] = 1;
        return;
      }
    }
    stop[p] = at;
  });
  for (size_t p = 0; p < pieces; ++p)
    if (refused[p]) {
      restore(start);
      return false;
    }
  size_t lines = 0, last = 0;
  for (size_t p = 0; p < pieces && first[p] < n; ++p) lines += ends[p], last = stop[p];
  line_ += lines;
  pos_ = last;
  token_line_ = line_;
  token_offset_ = pos_;
  return true;
}

void TextCursor::fail_line(uint64_t i, const std::string& problem) const {
  throw FormatError(path_ + ":" + std::to_string(lines_first_ + i) + ": " + problem);
}

std::string_view TextCursor::bytes(uint64_t n, const char* what) {
  token_offset_ = pos_;
  binary_ = true;
  if (n > data_.size() - pos_)
    fail("file ends: " + std::string(what) + " needs " + std::to_string(n) + " bytes, " +
         std::to_string(data_.size() - pos_) + " left");
  const std::string_view out = std::string_view(data_).substr(pos_, n);
  pos_ += n;
  return out;
}

double TextCursor::coordinate() {
  const double v = number<double>("a coordinate");
  if (!std::isfinite(v)) fail("coordinate is not finite");
  return v;
}

uint64_t TextCursor::count(const char* what, uint64_t limit) {
  const auto n = number<uint64_t>(what);
  if (n > limit) fail(std::string(what) + " " + std::to_string(n) + " is more than the file can hold");
  return n;
}

void TextCursor::expect(std::string_view keyword) {
  const std::string_view t = token(std::string(keyword).c_str());
  if (t != keyword) fail("expected '" + std::string(keyword) + "', found '" + std::string(t) + "'");
}

std::string TextCursor::where() const {
  if (binary_) return path_ + ": byte " + std::to_string(token_offset_);
  return path_ + ":" + std::to_string(token_line_);
}

void TextCursor::fail(const std::string& problem) const { throw FormatError(where() + ": " + problem); }

}  // namespace dtm
