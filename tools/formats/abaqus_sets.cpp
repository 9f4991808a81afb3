#include "abaqus_sets.h"

#include <algorithm>
#include <set>

#include "format_error.h"

namespace dtm::abaqus {

Set& Sets::at(const std::string& key, const std::string& name) {
  const auto [it, added] = index_.try_emplace(key, sets_.size());
  if (added) {
    Set& s = sets_.emplace_back();
    s.key = key, s.name = name;
  }
  return sets_[it->second];
}

const Set* Sets::find(const std::string& key) const {
  const auto it = index_.find(key);
  return it == index_.end() ? nullptr : &sets_[it->second];
}

const std::vector<int64_t>& Sets::resolved(const Set& s, std::span<const int64_t> defined,
                                           const std::string& path) const {
  if (const auto it = resolved_.find(&s); it != resolved_.end()) return it->second;
  std::vector<int64_t> out;
  const auto add = [&](int64_t n) {
    if (++numbers_ > kMostSetNumbers)
      throw FormatError(path + ": the sets hold more than " + std::to_string(kMostSetNumbers) +
                        " numbers in all");
    out.push_back(n);
  };
  // Every set it reaches, once (a set may name one that names it).
  std::set<const Set*> seen = {&s};
  std::vector<const Set*> todo = {&s};
  while (!todo.empty()) {
    const Set* t = todo.back();
    todo.pop_back();
    for (int64_t n : t->numbers) add(n);
    for (const Range& r : t->ranges) {
      // (Each range costs at most the defined numbers: its work is
      // bounded too, a step at a time.)
      const auto step = [&] {
        if (++work_ > kMostSetWork)
          throw FormatError(path + ": the sets' GENERATE ranges cover more than " +
                            std::to_string(kMostSetWork) + " numbers in all");
      };
      // (Range arithmetic in 128 bits: first + k step may pass 2^63.)
      const auto count = (static_cast<__int128>(r.last) - r.first) / r.step + 1;
      if (count <= static_cast<__int128>(defined.size())) {
        for (__int128 k = 0; k < count; ++k) {
          step();
          const auto n = static_cast<int64_t>(r.first + k * r.step);
          if (std::binary_search(defined.begin(), defined.end(), n)) add(n);
        }
      } else {
        for (auto it = std::lower_bound(defined.begin(), defined.end(), r.first);
             it != defined.end() && *it <= r.last; ++it, step())
          if ((static_cast<__int128>(*it) - r.first) % r.step == 0) add(*it);
      }
    }
    for (const std::string& key : t->includes) {
      const Set* u = find(key);
      if (!u)
        throw FormatError(path + ": set " + s.name.substr(0, 80) + " names a set " + key.substr(0, 80) +
                          " that the file does not define");
      if (seen.insert(u).second) todo.push_back(u);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return resolved_.emplace(&s, std::move(out)).first->second;
}

}  // namespace dtm::abaqus
