#!/usr/bin/env bash
# The Python package and the ParaView reader as a user gets them (ctest runs
# each step as a test of its own; docs/PYTHON.md and docs/PARAVIEW.md):
#   scripts/test_python.sh install BUILD   a venv over Debian's Python (its
#       numpy, meshio, pybind11, VTK), and `pip install ./python` into it,
#       with the extension module BUILD made
#   scripts/test_python.sh pytest BUILD    python/tests against BUILD's tools
#   scripts/test_python.sh paraview BUILD  pvbatch opens a stream with the
#       reader plugin, checks it against meshinfo, saves a screenshot
# Debian's Python, not another python3 on the PATH: its packages are the ones
# scripts/setup.sh installs, and ParaView runs on it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
step="$1"
build="$(cd "$2" && pwd)"
python="${DTM_SYSTEM_PYTHON:-/usr/bin/python3}"
venv="$build/python-venv"
export DTM_TOOLS="$build/tools" DTM_DATA="${DTM_DATA:-$root/data}"
case "$step" in
  install)
    rm -rf "$venv"
    "$python" -m venv --system-site-packages "$venv"
    # No build isolation: setuptools and pybind11 are Debian's (PyPI is not
    # reachable here). The extension module is the one BUILD made from its
    # own library objects (python/CMakeLists.txt), installed as it is.
    module=$(ls "$build"/python/_dtmesh*.so 2>/dev/null | head -1)
    [ -n "$module" ] || { echo "no _dtmesh module in $build/python: is pybind11-dev installed (scripts/setup.sh --all)?" >&2; exit 1; }
    DTMESH_PREBUILT_MODULE="$module" "$venv/bin/pip" install --no-build-isolation --no-deps -q "$root/python"
    "$venv/bin/python" -c "import dtmesh; print('dtmesh', dtmesh.__version__, 'installed in', '$venv')"
    ;;
  pytest)
    cd "$root/python/tests"
    "$venv/bin/python" -m pytest -q -p no:cacheprovider
    ;;
  paraview)
    stream="$build/paraview_reader.dtm"
    xz -dc "$DTM_DATA/bunny_10k.node.xz" > "$build/paraview_bunny.node"
    xz -dc "$DTM_DATA/bunny_10k.ele.xz" > "$build/paraview_bunny.ele"
    "$build/tools/meshenc" "$build/paraview_bunny.node" -q -o "$stream" --box 256 --dmax 2
    # A part of two materials (data/two_materials.geo): the regions as cell data.
    regions_stream="$build/paraview_regions.dtm"
    xz -dc "$DTM_DATA/two_materials.msh.xz" > "$build/paraview_regions.msh"
    # With an element result (gmsh $ElementData on every tetrahedron: its
    # element tag / 2), level 0's cell data.
    python3 - "$build/paraview_regions.msh" <<'PY'
import sys
path = sys.argv[1]
lines = open(path).read().split("\n")
at = lines.index("$Elements")
blocks = int(lines[at + 1].split()[0])
row, tags = at + 2, []
for _ in range(blocks):
    dim, entity, kind, count = map(int, lines[row].split())
    if kind == 4:  # 4-node tetrahedra
        tags += [int(lines[row + 1 + k].split()[0]) for k in range(count)]
    row += 1 + count
data = ["$ElementData", "1", '"density"', "1", "0.0", "3", "0", "1", str(len(tags))]
data += ["%d %.17g" % (t, t / 2) for t in tags] + ["$EndElementData"]
open(path, "a").write("\n".join(data) + "\n")
PY
    "$build/tools/meshenc" "$build/paraview_regions.msh" -q -o "$regions_stream"
    # pvbatch runs on Debian's Python: the venv's dtmesh is put on its path.
    site="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
    # pvbatch renders through GLX, so it needs an X server. In CI the server
    # has twice refused pvbatch ("bad X server connection"): once under
    # xvfb-run, once under an Xvfb that had announced its display through
    # -displayfd, with nothing in Xvfb's log either time. So the server is
    # not trusted until a client has really opened it (libX11's XOpenDisplay,
    # what VTK calls), a server that never lets one in is replaced by a fresh
    # one on another display, and what the machine's X sockets look like is
    # printed if every attempt fails.
    display_file="$build/paraview_xvfb.display" xvfb_log="$build/paraview_xvfb.log"
    xvfb=""
    trap '[ -z "$xvfb" ] || kill "$xvfb" 2>/dev/null || true' EXIT
    start_xvfb() {
      rm -f "$display_file"
      Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$display_file" 2>"$xvfb_log" &
      xvfb=$!
      for _ in $(seq 300); do
        grep -q '^[0-9][0-9]*$' "$display_file" 2>/dev/null && break
        kill -0 "$xvfb" 2>/dev/null || break
        sleep 0.1
      done
      grep -q '^[0-9][0-9]*$' "$display_file" 2>/dev/null || return 1
      # Up to 10 s for the announced display to accept a client.
      DISPLAY=":$(cat "$display_file")" "$python" -c '
import ctypes, sys, time
x11 = ctypes.CDLL("libX11.so.6")
x11.XOpenDisplay.restype = ctypes.c_void_p
x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
for _ in range(100):
    d = x11.XOpenDisplay(None)
    if d:
        x11.XCloseDisplay(d)
        sys.exit(0)
    time.sleep(0.1)
sys.exit(1)'
    }
    stop_xvfb() {
      kill "$xvfb" 2>/dev/null || true
      wait "$xvfb" 2>/dev/null || true
      xvfb=""
    }
    report_x() {
      echo "$1; Xvfb (display :$(cat "$display_file" 2>/dev/null)) said:" >&2
      cat "$xvfb_log" >&2
      ls -la /tmp/.X11-unix >&2 2>&1 || true
    }
    # Up to 3 servers; only a refused X connection is worth another try,
    # any other failure of pvbatch is the reader's and ends the test.
    pvbatch_out="$build/paraview_pvbatch.out"
    for attempt in 1 2 3; do
      if ! start_xvfb; then
        report_x "attempt $attempt: the X server did not let a client in"
        stop_xvfb
        continue
      fi
      if DISPLAY=":$(cat "$display_file")" PYTHONPATH="$site" pvbatch "$root/paraview/tests/check_reader.py" \
          "$root/paraview/dtmesh_reader.py" "$stream" "$build/tools/meshinfo" "$build/paraview_reader.png" \
          "$regions_stream" \
          > >(tee "$pvbatch_out") 2>&1; then
        exit 0
      fi
      report_x "attempt $attempt: pvbatch failed"
      grep -q "bad X server connection" "$pvbatch_out" || exit 1
      stop_xvfb
    done
    echo "no X server let pvbatch in after 3 attempts" >&2
    exit 1
    ;;
  *)
    echo "usage: $0 install|pytest|paraview BUILD" >&2
    exit 2
    ;;
esac
