"""What the tests of the Python package compare against: the project's own tools
(meshenc, meshdec, meshinfo of the C++ build), its golden streams, and the
corpus models of the repository's data/.

    DTM_TOOLS   the folder holding meshenc, meshdec and meshinfo (default: build/tools)
    DTM_DATA    the corpus (default: data/ of the repository)
"""
import lzma
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOLS = pathlib.Path(os.environ.get("DTM_TOOLS", ROOT / "build" / "tools"))
DATA = pathlib.Path(os.environ.get("DTM_DATA", ROOT / "data"))
GOLDEN = sorted((ROOT / "tests" / "golden").rglob("*.dtm"))
# The TetGen corpus models of about 10k vertices, encoded as the README's
# bench does (--box 256 --dmax 2).
CORPUS = ["bunny_10k", "elephant_10k", "fandisk_11k", "hand_10k", "knot1_10k", "torus_10k", "triceratops_10k"]
ENCODE_ARGS = ["--box", "256", "--dmax", "2"]


def tool(name):
    path = TOOLS / name
    if not path.exists():
        raise FileNotFoundError(f"{path}: build the tools first (scripts/build.sh) or set DTM_TOOLS")
    return str(path)


def run(*args):
    return subprocess.run([str(a) for a in args], check=True, capture_output=True).stdout


def read_tetgen(node_path):
    """A TetGen .node (+ .ele) as meshenc reads it: points, tetrahedra, fields in its order."""
    def rows(path):
        text = lzma.open(path, "rt") if str(path).endswith(".xz") else open(path)
        with text:
            return [line.split("#")[0].split() for line in text if line.split("#")[0].strip()]

    node = rows(node_path)
    count, _, attributes, markers = (int(v) for v in (node[0] + ["0", "0"])[:4])
    body = node[1 : 1 + count]
    base = int(body[0][0])
    points = np.array([[float(v) for v in r[1:4]] for r in body])
    fields = {}
    if attributes:
        fields["attributes"] = np.array([[float(v) for v in r[4 : 4 + attributes]] for r in body]).reshape(
            count, attributes) if attributes > 1 else np.array([float(r[4]) for r in body])
    if markers:
        fields["boundary_marker"] = np.array([int(r[4 + attributes]) for r in body], dtype=np.int32)
    ele_path = str(node_path).replace(".node", ".ele")
    tets = None
    if os.path.exists(ele_path):
        ele = rows(ele_path)
        tets = np.array([[int(v) - base for v in r[1:5]] for r in ele[1 : 1 + int(ele[0][0])]], dtype=np.int64)
    return points, tets, fields


@pytest.fixture(scope="session")
def corpus(tmp_path_factory):
    """name -> (the .node path, the stream meshenc made of it)."""
    folder = tmp_path_factory.mktemp("corpus")
    out = {}
    for name in CORPUS:
        for ext in ("node", "ele"):
            source = DATA / f"{name}.{ext}.xz"
            if not source.exists():  # a DTM_DATA that keeps its volumes in a subfolder
                source = DATA / "volumes" / f"{name}.{ext}.xz"
            (folder / f"{name}.{ext}").write_bytes(lzma.decompress(source.read_bytes()))
        stream = folder / f"{name}.dtm"
        run(tool("meshenc"), folder / f"{name}.node", "-q", "-o", stream, *ENCODE_ARGS)
        out[name] = (folder / f"{name}.node", stream)
    return out
