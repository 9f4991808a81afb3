#!/usr/bin/env bash
# tests/huge_pages.sh PROBE -- tools/huge_pages.h: a tool asks glibc for
# transparent huge pages (starting itself once more) exactly where the
# system gives them on request, keeps the user's own tunables, and leaves a
# user's choice (or DTM_HUGE_PAGES=0) alone.
set -euo pipefail
probe=$1
mode=$(cat /sys/kernel/mm/transparent_hugepage/enabled 2> /dev/null || echo none)
expect() {  # expect WANT ENV...
  local want=$1 got
  shift
  got=$(env -u GLIBC_TUNABLES -u DTM_HUGE_PAGES -u DTM_PROBE_STARTS "$@" "$probe")
  if [ "$got" != "$want" ]; then
    echo "huge_pages: with '$*' (THP mode '$mode'): expected '$want', got '$got'" >&2
    exit 1
  fi
}
case $mode in
  *"[madvise]"*)
    expect "2 glibc.malloc.hugetlb=1"
    expect "2 glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1" GLIBC_TUNABLES=glibc.malloc.arena_max=2
    ;;
  *)
    expect "1 (unset)"
    ;;
esac
expect "1 glibc.malloc.hugetlb=0" GLIBC_TUNABLES=glibc.malloc.hugetlb=0
expect "1 (unset)" DTM_HUGE_PAGES=0
echo "huge_pages: ok (THP mode: $mode)"
