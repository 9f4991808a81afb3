#include "text_cursor.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace dtm {

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot open file");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw FormatError(path + ": cannot read file");
  return std::move(s).str();
}

TextCursor::TextCursor(std::string path, std::string bytes, char comment)
    : path_(std::move(path)), data_(std::move(bytes)), comment_(comment) {}

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
