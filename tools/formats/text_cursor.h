// A strict cursor over a whole input file for the small readers of our own
// (Medit, VTK legacy, gmsh, NRRD headers): whitespace-separated tokens, whole
// lines and raw binary bytes, with errors that say where. Errors in text name
// the line ("path:12: problem"); once binary bytes have been read they name
// the byte offset ("path: byte 4096: problem").
#pragma once

#include <charconv>
#include <cstdint>
#include <functional>
#include <istream>
#include <string>
#include <string_view>

#include "format_error.h"

namespace dtm {

// A UTF-8 byte-order mark, which Windows editors put first in a file: a
// text reader skips it.
inline constexpr std::string_view kUtf8ByteOrderMark = "\xef\xbb\xbf";
// `in` past a byte-order mark at its start (left where it was otherwise).
inline void skip_byte_order_mark(std::istream& in) {
  const std::streampos start = in.tellg();
  char head[3] = {};
  in.read(head, sizeof head);
  if (static_cast<size_t>(in.gcount()) == sizeof head &&
      std::string_view(head, sizeof head) == kUtf8ByteOrderMark)
    return;
  in.clear();
  in.seekg(start);
}

// The bytes of `path`; throws FormatError "path: cannot open file".
std::string read_whole_file(const std::string& path);

// The whole of `text` as a T (from_chars: no sign '+', no blanks).
template <class T>
bool parse_whole(std::string_view text, T& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size();
}

// The next field of a line, split at blanks (' ', '\t', '\r'), from `at`,
// `at` moved past it ("" at the end of the line).
inline std::string_view next_field(std::string_view line, size_t& at) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (at < line.size() && blank(line[at])) ++at;
  const size_t b = at;
  while (at < line.size() && !blank(line[at])) ++at;
  return line.substr(b, at - b);
}

class TextCursor {
 public:
  // `comment`: a character that starts a comment running to the end of the
  // line ('\0' = none); tokens skip comments, lines do not.
  TextCursor(std::string path, std::string bytes, char comment = '\0');
  static TextCursor open(const std::string& path, char comment = '\0') {
    return TextCursor(path, read_whole_file(path), comment);
  }

  const std::string& path() const { return path_; }
  // True when only whitespace and comments are left.
  bool at_end();
  // The next token; fails with "file ends, expected <what>" at the end.
  std::string_view token(const char* what);
  // The next token without moving the cursor ("" at the end).
  std::string_view peek();
  // The rest of the current line (without '\r\n'), then moves to the next
  // line. At the end of a line, the (empty) rest of it.
  std::string_view rest_of_line();
  // Skips whitespace up to and including the end of the current line.
  void skip_to_next_line();
  // The next `n` lines, as n calls of rest_of_line() would give them, each
  // handed to parse(i, line) on one of every core's threads (the lines cut
  // into pieces at line ends first, in one pass). parse() fails with
  // fail_line(i, ...); the failure of the earliest line is the one thrown
  // here, as a loop over the lines would throw it.
  void lines(uint64_t n, const std::function<void(uint64_t, std::string_view)>& parse);
  // The next `n` tokens (as n calls of token() would give them), each
  // handed to parse(i, token) on one of every core's threads, the text cut
  // into pieces between tokens first. False, with the cursor where it was,
  // when parse() refuses one or the file has fewer (or the cursor skips
  // comments): the caller then reads them one by one, with their errors.
  bool tokens(uint64_t n, const std::function<bool(uint64_t, std::string_view)>& parse);
  // For lines()' parse(): "path:L: problem", L the line of its line i.
  [[noreturn]] void fail_line(uint64_t i, const std::string& problem) const;
  // A place to come back to (restore()): a reader that tried a fast way
  // through a section reads it again the strict way.
  struct Mark {
    size_t pos, line;
  };
  Mark mark() const { return {pos_, line_}; }
  void restore(const Mark& m) { pos_ = m.pos, line_ = m.line; }
  // `n` raw bytes from the current position.
  std::string_view bytes(uint64_t n, const char* what);
  size_t offset() const { return pos_; }
  uint64_t remaining() const { return data_.size() - pos_; }
  // Everything after the current position.
  std::string_view rest() const { return std::string_view(data_).substr(pos_); }

  template <class T>
  T number(const char* what) {
    const std::string_view t = token(what);
    T value{};
    if (!parse_whole(t, value)) fail(std::string("expected ") + what + ", found '" + std::string(t) + "'");
    return value;
  }
  // A finite double.
  double coordinate();
  // A count no larger than `limit` (what the rest of the file could hold).
  uint64_t count(const char* what, uint64_t limit);
  void expect(std::string_view keyword);

  // Where the last token started: "path:line" for text, "path: byte N" after
  // binary data.
  std::string where() const;
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  void skip_space();

  std::string path_;
  std::string data_;
  char comment_;
  size_t pos_ = 0;
  size_t line_ = 1;        // line of pos_
  size_t token_line_ = 1;  // line where the last token started
  size_t token_offset_ = 0;
  size_t lines_first_ = 1;  // the line of lines()' first line
  bool binary_ = false;     // binary bytes have been read: report offsets
};

}  // namespace dtm
