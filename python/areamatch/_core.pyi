# Type stubs of the compiled module (python/src/module.cpp), so editors complete the API.
import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_THREADS: int
FREE: int
OCCUPIED: int
UNKNOWN: int

Origin = Tuple[float, float, float]

class Map:
    @staticmethod
    def from_array(image: npt.NDArray[Any], resolution: float, origin: Origin = ..., free_thresh: float = ...,
                   occupied_thresh: float = ..., negate: bool = ...) -> Map: ...
    @staticmethod
    def from_occupancy_grid(data: Any, width: int, height: int, resolution: float, origin: Origin = ...,
                            free_thresh: float = ..., occupied_thresh: float = ...) -> Map: ...
    def to_occupancy_grid(self) -> Dict[str, Any]: ...
    def to_image(self) -> npt.NDArray[np.uint8]: ...
    def save(self, image_path: str) -> str: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def resolution(self) -> float: ...
    @property
    def origin(self) -> Origin: ...
    @property
    def cells(self) -> npt.NDArray[np.uint8]: ...
    def counts(self) -> Dict[str, int]: ...
    def world_from_pixel(self) -> npt.NDArray[np.float64]: ...
    def copy(self) -> Map: ...
    def __eq__(self, other: object) -> bool: ...
    def __ne__(self, other: object) -> bool: ...

def load_map(path: Union[str, os.PathLike[str]], resolution: Optional[float] = ..., free_thresh: Optional[float] = ...,
             occupied_thresh: Optional[float] = ..., negate: Optional[bool] = ...) -> Map: ...

class Passage:
    id: int
    kind: str
    position: npt.NDArray[np.float64]
    width_m: float
    areas: Tuple[int, int]
    line: npt.NDArray[np.float64]

class Area:
    id: int
    kind: str
    polygon: npt.NDArray[np.float64]
    holes: List[npt.NDArray[np.float64]]
    convex_hull: npt.NDArray[np.float64]
    size_m2: float
    centroid: npt.NDArray[np.float64]
    max_clearance_m: float
    passages: List[int]

class AreaGraph:
    areas: List[Area]
    passages: List[Passage]
    covered_fraction: float
    reason: str
    def adjacency(self) -> List[List[int]]: ...
    def labels(self) -> npt.NDArray[np.int32]: ...
    def to_json(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def picture(self, map: Map) -> Picture: ...
    def __len__(self) -> int: ...

def segment(map: Map, door_width_m: Optional[float] = ...) -> AreaGraph: ...

class Picture:
    width: int
    height: int
    def save(self, path: str) -> None: ...

class Result:
    ok: bool
    reason: str
    T_dest_source: npt.NDArray[np.float64]
    pixel_transform: npt.NDArray[np.float64]
    rotation: float
    rotation_deg: float
    translation_m: npt.NDArray[np.float64]
    scale: float
    scale_estimated: bool
    reflected: bool
    score: float
    margin: float
    ambiguous: bool
    p_correct: float
    source_map: Map
    dest_map: Map
    source_graph: AreaGraph
    dest_graph: AreaGraph
    # Read natively, with the keys of to_dict() (matched_areas wrapped in areamatch/__init__.py):
    evidence: Dict[str, Any]
    matched_areas: List[Dict[str, Any]]  # MatchedArea objects: dicts read as attributes too
    rejection: Optional[str]  # 'different places', 'not sure', 'no answer'; None when ok
    statistics: Dict[str, int]
    timings: Dict[str, float]
    margin_different: Optional[float]
    margin_mirrored: Optional[float]
    def to_json(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def picture(self) -> Picture: ...

def match(source: Map, dest: Map, *, allow_reflection: bool = ..., estimate_scale: bool = ...,
          door_width_m: Optional[float] = ..., source_door_width_m: Optional[float] = ...,
          dest_door_width_m: Optional[float] = ..., k: Optional[int] = ..., min_score: Optional[float] = ...,
          min_agreement: Optional[float] = ..., gate_max_lower_walls: Optional[float] = ...,
          gate_min_overlap_m2: Optional[float] = ..., min_p_correct: Optional[float] = ..., paper: bool = ...,
          threads: int = ..., progress: Optional[Callable[[str, int, int], None]] = ...,
          params: Optional[Dict[str, Any]] = ...) -> Result: ...

def parameters(*, paper: bool = ...) -> List[Dict[str, Any]]: ...

class Assessment:
    ok: bool
    reason: str
    decision_overridden: bool
    broken_pieces: int
    explored_share: float
    def warp_points(self, pixels: npt.ArrayLike) -> npt.NDArray[np.float64]: ...
    def to_json(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def picture(self, error_scale_m: float = ...) -> Picture: ...

def assess(map: Map, reference: Map, *, same_building: bool = ..., allow_reflection: bool = ...,
           door_width_m: Optional[float] = ..., map_door_width_m: Optional[float] = ...,
           reference_door_width_m: Optional[float] = ..., min_agreement: Optional[float] = ...,
           min_p_correct: Optional[float] = ..., control_spacing_m: Optional[float] = ...,
           bend_length_m: Optional[float] = ...) -> Assessment: ...

class PreparedMap:
    map: Map
    graph: AreaGraph

class MergeResult:
    ok: bool
    reference: int
    maps: List[Dict[str, Any]]
    merged: Map
    edges: List[Dict[str, Any]]
    timings: Dict[str, float]
    def edge_results(self) -> List[Tuple[int, int, Result]]: ...
    def to_json(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def picture(self) -> Picture: ...

class Matcher:
    def __init__(self, *, door_width_m: Optional[float] = ..., allow_reflection: bool = ..., k: Optional[int] = ...,
                 min_score: Optional[float] = ..., min_agreement: Optional[float] = ...,
                 gate_max_lower_walls: Optional[float] = ..., gate_min_overlap_m2: Optional[float] = ...,
                 min_p_correct: Optional[float] = ..., threads: int = ...,
                 params: Optional[Dict[str, Any]] = ...) -> None: ...
    def prepare(self, map: Map) -> PreparedMap: ...
    def prepare_all(self, maps: Sequence[Map], threads: int = ...) -> List[PreparedMap]: ...
    @overload
    def match(self, source: PreparedMap, dest: PreparedMap) -> Result: ...
    @overload
    def match(self, source: Map, dest: PreparedMap) -> Result: ...
    @overload
    def match(self, source: Map, dest: Map) -> Result: ...
    def merge(self, maps: Sequence[PreparedMap], *, reference: Optional[int] = ..., resolution: Optional[float] = ...,
              wall_share: float = ..., max_residual_m: float = ..., until_connected: bool = ..., same_side: bool = ..., threads: int = ...,
              names: Sequence[str] = ..., build_merged_map: bool = ..., non_rigid: bool = ...,
              control_spacing_m: Optional[float] = ..., bend_length_m: Optional[float] = ...) -> MergeResult: ...
