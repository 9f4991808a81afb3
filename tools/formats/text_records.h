// A text file of one record a line (TetGen's .node and .ele), its fields
// split and parsed on every core: the file is read in blocks of whole
// lines, each block cut into pieces at line ends, and each piece parsed on
// its own thread, each record told its number and its line's. '#' starts a
// comment; blank lines (and commas between fields) are skipped, as TetGen
// reads them.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "format_error.h"

namespace dtm {

class TextRecords {
 public:
  using Fields = std::vector<std::string_view>;
  // Throws FormatError when the file cannot be opened. `block_bytes`: the
  // text read at once (a test's small blocks cross many line ends).
  explicit TextRecords(const std::string& path, size_t block_bytes = size_t{32} << 20);

  // The next meaningful line's fields, on the calling thread (a header);
  // false at the end of the file.
  bool next(Fields& fields);
  // The line number of the last line next() returned.
  size_t line() const { return line_; }

  // Restricts what records() reads to part `part` of `parts` of the rest
  // of the file (an MPI rank's range): the lines whose first byte lies in
  // that part of its bytes. Call it after next() has read the header,
  // before records(); the parts' records, joined in part order, are the
  // file's. The lines records() numbers skip the earlier parts' (counting
  // them would read almost the whole file on the last rank), which fail()
  // adds back: its message names the line in the whole file.
  void keep_to_part(int part, int parts);

  struct Found {
    uint64_t records = 0;   // records parsed (at most `count`)
    size_t extra_line = 0;  // the line of a meaningful line past them (0: none)
  };
  // The next `count` meaningful lines: for each block, start(n, bytes) on
  // the calling thread with the n records it holds in its bytes of text,
  // then parse(i, line, fields) for i in [0, n) on every core, then
  // finish() on the calling thread. An exception parse throws stops the
  // reading; the one of the earliest line is thrown again here, as a loop
  // over the lines would throw it.
  Found records(uint64_t count, const std::function<void(size_t, size_t)>& start,
                const std::function<void(size_t, size_t, const Fields&)>& parse,
                const std::function<void()>& finish);

  [[noreturn]] void fail(size_t line, const std::string& problem) const;
  // Of n records of `fields` fields each in `bytes` of text, how many can
  // be whole: each takes two bytes a field at least (a character and a
  // separator or the line end; the last line of a file may lack its end,
  // hence the byte added). Room for that many is all a block needs: when
  // record i is past it and has its fields, a record before i has not, and
  // the error is that record's (an earlier line). So a line of one
  // character cannot claim room for a record of many fields.
  static size_t room(size_t n, size_t bytes, size_t fields) {
    return std::min(n, (bytes + 1) / (2 * std::max<size_t>(fields, 1)));
  }
  // A field as a T, the whole of it, or fail(line, "expected WHAT, ...").
  template <class T>
  T parse(std::string_view token, const char* what, size_t line) const {
    T value{};
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size())
      fail(line, std::string("expected ") + what + ", found '" + std::string(token) + "'");
    return value;
  }

 private:
  // Reads the next block of whole lines into text_ (false at the end).
  bool read_block();

  std::string path_;
  std::ifstream in_;
  size_t block_bytes_;
  std::string text_;   // the block: whole lines
  std::string carry_;  // a line begun at the end of the last read
  size_t at_ = 0;      // next() and records() go on from here in text_
  size_t line_ = 0;    // the line of text_[at_ - 1]'s line (lines before at_)
  bool eof_ = false;
  uint64_t read_ = 0;                      // bytes read from in_
  uint64_t left_ = UINT64_MAX;             // bytes read_block() may still read (keep_to_part())
  std::pair<uint64_t, uint64_t> skipped_;  // bytes keep_to_part() skipped, lines uncounted
};

}  // namespace dtm
