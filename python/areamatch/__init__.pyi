from typing import Any, Dict, List, Optional, Sequence

from . import ros as ros, synthetic as synthetic
from .errors import (Error as Error, FormatError as FormatError, InternalError as InternalError, IoError as IoError,
                     LimitError as LimitError, ParameterError as ParameterError)
from ._core import (DEFAULT_THREADS as DEFAULT_THREADS, FREE as FREE, OCCUPIED as OCCUPIED, UNKNOWN as UNKNOWN, Area as Area, AreaGraph as AreaGraph,
                    Assessment as Assessment, Map as Map, Matcher as Matcher, MergeResult as MergeResult, Passage as Passage, Picture as Picture,
                    PreparedMap as PreparedMap, Result as Result, __version__ as __version__, assess as assess, load_map as load_map,
                    match as match, parameters as parameters, segment as segment)

class MatchedArea(Dict[str, Any]):
    source: int
    dest: int
    overlap: float
    iou: float
    local_rotation_deg: float
    local_translation_m: List[float]
    wall_agreement: float

def merge(maps: Sequence[Map], *, reference: int = ..., door_width_m: Optional[float] = ..., allow_reflection: bool = ...,
          min_agreement: Optional[float] = ..., gate_max_lower_walls: Optional[float] = ...,
          gate_min_overlap_m2: Optional[float] = ..., min_p_correct: Optional[float] = ..., resolution: Optional[float] = ...,
          wall_share: float = ..., max_residual_m: float = ..., until_connected: bool = ..., same_side: bool = ..., threads: int = ...,
          names: Optional[Sequence[str]] = ..., build_merged_map: bool = ..., non_rigid: bool = ...,
          control_spacing_m: Optional[float] = ..., bend_length_m: Optional[float] = ...) -> MergeResult: ...
