// Prints GLIBC_TUNABLES as a tool sees it after tools/huge_pages.h's
// ask_for_huge_pages (tests/huge_pages.sh checks it), and how many times
// main() began in this process (1: not started again; 2: started again).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tools/huge_pages.h"

int main(int, char** argv) {
  const char* before = std::getenv("DTM_PROBE_STARTS");
  const int starts = (before ? std::atoi(before) : 0) + 1;
  setenv("DTM_PROBE_STARTS", std::to_string(starts).c_str(), 1);
  dtm::ask_for_huge_pages(argv);
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::printf("%d %s\n", starts, tunables ? tunables : "(unset)");
  return 0;
}
