// Transparent huge pages for the tools' large arrays. Decoding or encoding a
// million vertices touches about a gigabyte of fresh memory, and with 4 KiB
// pages every page costs a fault: on this project's 2-core machine (a VM)
// faults took a quarter of meshdec's time, and a sequential CGAL
// construction runs 1.15x faster too (bench/results/HUGE_PAGES.md). Linux gives huge pages to
// every allocation only where /sys/kernel/mm/transparent_hugepage/enabled is
// "always"; Debian's default, "madvise", gives them to memory that asks,
// which glibc's malloc does when its tunable glibc.malloc.hugetlb=1 is set.
// Tunables are read when a process starts, so a tool sets it by starting
// itself again.
#pragma once

namespace dtm {

// Called first in main(), before any thread or MPI starts: where the system
// gives huge pages on request and GLIBC_TUNABLES does not already say what
// glibc.malloc.hugetlb is, sets it to 1 and replaces this process with the
// same program and arguments (/proc/self/exe). Returns where it does not:
// DTM_HUGE_PAGES=0, the setting already there (the user's or the second
// start's), "always" or "never", or an exec that failed (the tool then runs
// as it is).
void ask_for_huge_pages(char** argv);

}  // namespace dtm
