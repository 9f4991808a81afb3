// An Abaqus file's sets of nodes or elements (*NSET, *ELSET, and the
// NSET= and ELSET= of *NODE and *ELEMENT): numbers, GENERATE ranges and
// other sets by name, resolved once each to the numbers they hold, with
// bounds on what a small file can make the reader do.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace dtm::abaqus {

struct Range {
  int64_t first = 0, last = 0, step = 1;
};

struct Set {
  std::string key;   // upper case (an assembly's: "ASSEMBLY." + it)
  std::string name;  // as first written (an assembly's: "assembly." + it)
  std::vector<int64_t> numbers;
  std::vector<Range> ranges;              // GENERATE's
  std::vector<std::string> includes;      // the keys of the sets it names
  std::vector<std::string> element_sets;  // a node set's ELSET=: its elements' nodes
  bool from_element_lines = false;        // *ELEMENT's ELSET= (or *NODE's NSET=)
  bool internal = false;                  // INTERNAL (Abaqus/CAE's own)
  bool assembly = false;                  // defined in an *ASSEMBLY
};

// The most numbers the sets may resolve to in all (8 bytes each).
inline constexpr uint64_t kMostSetNumbers = uint64_t{1} << 26;
// The most numbers their GENERATE ranges may cover in all.
inline constexpr uint64_t kMostSetWork = uint64_t{1} << 28;

class Sets {
 public:
  // The set of `key` (upper case), made on first use with `name`.
  Set& at(const std::string& key, const std::string& name);
  const Set* find(const std::string& key) const;
  const std::deque<Set>& all() const { return sets_; }

  // The numbers of `s` and of the sets it names, ascending, each once: its
  // own numbers, and of its ranges those in `defined` (ascending: a range
  // reaching past what is defined is read through them). Resolved once a
  // set. Throws FormatError (naming `path`) when it names a set that is not
  // defined, or when the sets resolve to more than kMostSetNumbers numbers.
  const std::vector<int64_t>& resolved(const Set& s, std::span<const int64_t> defined,
                                       const std::string& path) const;

 private:
  std::deque<Set> sets_;
  std::map<std::string, size_t> index_;
  mutable std::map<const Set*, std::vector<int64_t>> resolved_;
  mutable uint64_t numbers_ = 0, work_ = 0;
};

}  // namespace dtm::abaqus
