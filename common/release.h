// Gives a container's memory back. `v = {}` does not: for a std::vector it
// picks the initializer_list assignment, which empties the vector and keeps
// its capacity (at 10M vertices, a gigabyte of tetrahedra stayed held).
#pragma once

#include <utility>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace dtm {

template <class Container>
void release(Container& c) {
  Container().swap(c);
}

// Hands the heap's free pages back to the system (glibc's malloc_trim): for
// a program that lets malloc keep what is freed between the phases of one
// piece of work (meshenc: tools/tool_main.h), called where one piece ends
// and the next begins (a level of the hierarchy, the stream after the
// levels), so that what one level freed does not add to the next one's
// peak. Elsewhere it costs a pass over the heap's free lists.
inline void give_back_free_heap() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

}  // namespace dtm
