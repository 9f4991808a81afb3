#!/usr/bin/env bash
# The Python package and the ParaView reader as a user gets them (ctest runs
# each step as a test of its own; README "Python" and "ParaView"):
#   scripts/test_python.sh install BUILD   a venv over Debian's Python (its
#       numpy, meshio, pybind11, VTK), and `pip install ./python` into it
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
export DTM_TOOLS="$build/tools" DTM_DATA="${DTM_DATA:-$root/../shared/data}"
case "$step" in
  install)
    rm -rf "$venv"
    "$python" -m venv --system-site-packages "$venv"
    # No build isolation: the build's setuptools and pybind11 are Debian's
    # (PyPI is not reachable here). The C++ library is built with PIC in
    # BUILD/python-cmake, once; later installs rebuild what changed.
    DTMESH_CMAKE_BUILD="$build/python-cmake" "$venv/bin/pip" install --no-build-isolation --no-deps -q \
      "$root/python"
    "$venv/bin/python" -c "import dtmesh; print('dtmesh', dtmesh.__version__, 'installed in', '$venv')"
    ;;
  pytest)
    cd "$root/python/tests"
    "$venv/bin/python" -m pytest -q -p no:cacheprovider
    ;;
  paraview)
    stream="$build/paraview_reader.dtm"
    xz -dc "$DTM_DATA/volumes/bunny_10k.node.xz" > "$build/paraview_bunny.node"
    xz -dc "$DTM_DATA/volumes/bunny_10k.ele.xz" > "$build/paraview_bunny.ele"
    "$build/tools/meshenc" "$build/paraview_bunny.node" -q -o "$stream" --box 256 --dmax 2
    # pvbatch runs on Debian's Python: the venv's dtmesh is put on its path.
    site="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
    # pvbatch renders through GLX, so it needs an X server. Under xvfb-run
    # the server once refused pvbatch in CI ("bad X server connection") and
    # xvfb-run had thrown Xvfb's messages away; so Xvfb is started here:
    # -displayfd picks a free display and writes its number only once the
    # server listens, and whatever Xvfb says is shown if anything fails.
    display_file="$build/paraview_xvfb.display" xvfb_log="$build/paraview_xvfb.log"
    rm -f "$display_file"
    Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$display_file" 2>"$xvfb_log" &
    xvfb=$!
    trap 'kill "$xvfb" 2>/dev/null || true' EXIT
    for _ in $(seq 300); do
      grep -q '^[0-9][0-9]*$' "$display_file" 2>/dev/null && break
      kill -0 "$xvfb" 2>/dev/null || break
      sleep 0.1
    done
    if ! grep -q '^[0-9][0-9]*$' "$display_file" 2>/dev/null; then
      echo "Xvfb did not start; it said:" >&2
      cat "$xvfb_log" >&2
      exit 1
    fi
    if ! DISPLAY=":$(cat "$display_file")" PYTHONPATH="$site" pvbatch "$root/paraview/tests/check_reader.py" \
        "$root/paraview/dtmesh_reader.py" "$stream" "$build/tools/meshinfo" "$build/paraview_reader.png"; then
      echo "pvbatch failed; Xvfb said:" >&2
      cat "$xvfb_log" >&2
      exit 1
    fi
    ;;
  *)
    echo "usage: $0 install|pytest|paraview BUILD" >&2
    exit 2
    ;;
esac
