"""One call of the Python package in this process, as bench_hierarchy --peak-memory
times the same call in C++: prints seconds and peak RSS (MiB) before and after.

    python_bindings.py MODEL.node encode   # dtmesh.encode of its points and .ele, box 256, Dmax 2
    python_bindings.py MODEL.dtm decode    # dtmesh.decode of the stream, the finest level

Run by bench/python.sh, one fresh process per call (ru_maxrss is a high-water mark).
"""
import pathlib
import resource
import sys
import time

import numpy as np

import dtmesh

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "python" / "tests"))
from conftest import read_tetgen  # noqa: E402


def rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


path, what = sys.argv[1:3]
if what == "encode":
    # The arrays from an .npz beside the model, made once by another process:
    # parsing the text here would leave its own high-water mark.
    cache = pathlib.Path(path).with_suffix(".npz")
    if not cache.exists():
        import subprocess

        subprocess.run([sys.executable, __file__, path, "cache"], check=True)
    arrays = np.load(cache)
    points, tets = arrays["points"], arrays["tetrahedra"]  # no fields: bench_hierarchy encodes none
    loaded = rss_mib()
    start = time.perf_counter()
    result = dtmesh.encode(points, tets, box=256, dmax=2)
    count = len(points)
elif what == "cache":
    points, tets, _ = read_tetgen(path)
    np.savez(pathlib.Path(path).with_suffix(".npz"), points=points, tetrahedra=tets)
    sys.exit(0)
else:
    data = pathlib.Path(path).read_bytes()
    loaded = rss_mib()
    start = time.perf_counter()
    result = dtmesh.decode(data)
    count = len(result.points)
seconds = time.perf_counter() - start
print(f"model={pathlib.Path(path).stem} call={what} vertices={count} seconds={seconds:.3f} "
      f"loaded_rss_mib={loaded:.1f} peak_rss_mib={rss_mib():.1f}")
