#!/usr/bin/env bash
# scripts/view.sh FILE.dtm [--port N] [--rate 500KB/s]
#
# Shows a .dtm stream in the browser viewer: builds the WebAssembly decoder
# and the page if they are missing or older than their sources
# (scripts/build_web.sh), then serves the page and FILE on 127.0.0.1 only,
# until interrupted, and prints the URL to open. --rate throttles the stream
# (decimal units: 500KB/s, 1MB/s) so that its levels visibly arrive one by
# one; --port picks the port (default: any free one).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
usage() { sed -n '2,10s/^# \{0,1\}//p' "$0"; }
file="" serve_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --port|--rate)
      [ $# -ge 2 ] || { echo "view.sh: $1 needs a value" >&2; exit 2; }
      serve_args+=("$1" "$2"); shift 2 ;;
    --port=*|--rate=*) serve_args+=("$1"); shift ;;
    -*) echo "view.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) [ -z "$file" ] || { echo "view.sh: one file at a time" >&2; exit 2; }; file=$1; shift ;;
  esac
done
[ -n "$file" ] || { usage >&2; exit 2; }
[ -f "$file" ] || { echo "view.sh: $file: no such file" >&2; exit 1; }
log="$root/build-wasm/build_web.log"
mkdir -p "$root/build-wasm"
echo "view.sh: building the viewer if needed (log: $log)" >&2
if ! "$root/scripts/build_web.sh" > "$log" 2>&1; then
  tail -20 "$log" >&2
  echo "view.sh: building the viewer failed (log: $log)" >&2
  exit 1
fi
echo "view.sh: serving $file on 127.0.0.1 until interrupted (Ctrl-C); open:" >&2
exec python3 "$root/scripts/serve.py" "$root/build-wasm/dist" "$file" "${serve_args[@]}"
