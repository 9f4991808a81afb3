// Gives a container's memory back. `v = {}` does not: for a std::vector it
// picks the initializer_list assignment, which empties the vector and keeps
// its capacity (at 10M vertices, a gigabyte of tetrahedra stayed held).
#pragma once

#include <utility>

namespace dtm {

template <class Container>
void release(Container& c) {
  Container().swap(c);
}

}  // namespace dtm
