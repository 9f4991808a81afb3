# Types of the extension module under dtmesh (python/src/dtmesh_module.cpp).
# Use the package's functions (dtmesh.encode, dtmesh.decode, dtmesh.Decoder,
# dtmesh.decode_box, dtmesh.decode_piece, dtmesh.info): they check and shape what they hand this module.
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

version: str
default_max_vertices: int

def set_error_type(type: type) -> None: ...
def split_cells(
    cells: npt.NDArray[np.int64], points: npt.NDArray[np.float64]
) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]: ...

class FieldIn:
    def __init__(self, name: str, type: int, components: int, values: npt.NDArray[np.float64]) -> None: ...

def encode(
    points: npt.NDArray[np.float64],
    tetrahedra: Optional[npt.NDArray[np.int64]],
    regions: Optional[npt.NDArray[np.int64]],
    region_names: Mapping[int, str],
    faces: Optional[npt.NDArray[np.int64]],
    face_tags: Optional[npt.NDArray[np.int64]],
    face_tag_names: Mapping[int, str],
    fields: List[FieldIn],
    cell_fields: List[FieldIn],
    qbits: int,
    box: Optional[float],
    scale: Optional[float],
    dmax: Optional[float],
    preset: str,
    field_errors: Mapping[str, float],
    keep_order: bool,
    exact: bool,
    bricks: bool,
    brick_points: int,
    edge_points: Optional[npt.NDArray[np.float64]],
    edge_nodes: Optional[npt.NDArray[np.int64]],
    edge_fields: List[FieldIn],
    node_numbering: Optional[npt.NDArray[np.int64]],
) -> Tuple[bytes, str, npt.NDArray[np.uint32]]: ...

class Decoder:
    def __init__(self, stop_after_level: int, max_vertices: int) -> None: ...
    def feed(self, chunk: bytes, meshes: bool) -> List[Union[int, Dict[str, Any]]]: ...
    def finish(self) -> Optional[str]: ...
    def done(self) -> bool: ...
    def finest_level(self) -> int: ...
    def level_count(self) -> int: ...
    def mesh(self) -> Dict[str, Any]: ...

def decode_part(
    data: Union[bytes, str],
    box: Optional[Tuple[float, float, float, float, float, float]],
    piece: int,
    pieces: int,
    level: int,
    max_vertices: int,
) -> Dict[str, Any]: ...
def info(data: bytes, stats: bool) -> str: ...
def set_threads(threads: int) -> None: ...
def threads() -> int: ...
