"""areamatch: align 2D occupancy-grid maps of one building and say which room is which.

    import areamatch
    robot = areamatch.load_map("robot.yaml")
    layout = areamatch.load_map("layout.yaml")
    result = areamatch.match(robot, layout)
    if result.ok:
        print(result.T_dest_source)          # 3x3, robot world -> layout world (metres)

Everything is computed by the C++ library (areamatch._core); the GIL is released while maps are
loaded, segmented, matched and merged. Every library error is an areamatch.Error (and, as before,
a ValueError for parameters and file content, an OSError for files). See docs/python.md.
"""

from ._core import (  # noqa: F401
    DEFAULT_THREADS,
    FREE,
    OCCUPIED,
    UNKNOWN,
    Area,
    AreaGraph,
    Assessment,
    Map,
    Matcher,
    MergeResult,
    Passage,
    Picture,
    PreparedMap,
    Result,
    __version__,
    assess,
    load_map,
    match,
    parameters,
    segment,
)
from . import ros, synthetic  # noqa: F401
from .errors import Error, FormatError, InternalError, IoError, LimitError, ParameterError  # noqa: F401

import inspect as _inspect


def _takes_maps(function, names):
    """`function` with a clear TypeError when a path is passed where it takes a Map."""
    import functools
    import os

    @functools.wraps(function)
    def checked(*args, **kwargs):
        given = list(args[:len(names)]) + [kwargs[n] for n in names if n in kwargs]
        for value in given:
            if isinstance(value, (str, bytes, os.PathLike)):
                raise TypeError(f"areamatch.{function.__name__} takes Maps, not paths: load it first, "
                                f"areamatch.load_map({value!r})")
        return function(*args, **kwargs)
    return checked


match = _takes_maps(match, ("source", "dest"))
segment = _takes_maps(segment, ("map",))
assess = _takes_maps(assess, ("map", "reference"))


# Result.evidence, statistics, timings, rejection and the margins, and MergeResult.edges and
# timings, are read natively from the result (the keys and values of `areamatch match --json` /
# `merge --json`, docs/cli.md); matched_areas wraps the native dicts as MatchedArea.
class MatchedArea(dict):
    """One room correspondence of a match, read as attributes (`a.source`, `a.dest`, `a.iou`) or,
    as before, as dict keys: source and dest (area ids), overlap, iou, local_rotation_deg,
    local_translation_m (the room's own fit: its transform, source world -> destination world, beside
    the whole map's T_dest_source), wall_agreement."""

    def __getattr__(self, key):
        try:
            return self[key]
        except KeyError:
            raise AttributeError(f"MatchedArea has no field {key!r}; it has {', '.join(self)}") from None

    def __repr__(self):
        return (f"MatchedArea(source={self['source']}, dest={self['dest']}, iou={self['iou']:.3f}, "
                f"local_rotation_deg={self['local_rotation_deg']:.2f})")


Result.matched_areas = property(
    lambda self: [MatchedArea(a) for a in self._matched_area_dicts],
    doc="Room correspondences (list of MatchedArea: source, dest, overlap, iou, local_rotation_deg, ...).")


def merge(maps, *, reference=0, door_width_m=None, allow_reflection=False, min_agreement=None,
          gate_max_lower_walls=None, gate_min_overlap_m2=None, min_p_correct=None, resolution=None, wall_share=0.5, max_residual_m=1.0,
          until_connected=False, same_side=True, threads=DEFAULT_THREADS, names=None, build_merged_map=True, non_rigid=False,
          control_spacing_m=None, bend_length_m=None):
    """Places several maps of one building in the frame of maps[reference] and fuses them.

    As `areamatch merge`: every pair matched (or only until connected), the poses fitted to the
    accepted matches, contradicted matches dropped, unplaced maps reported with a reason.
    `maps`: Map objects, prepared here `threads` at a time (maps prepared already: Matcher.merge).
    `same_side`: refine each accepted match by ICP that pairs walls only with walls facing the
    same way (MergeParams::refine_same_side). `non_rigid`: bend each map onto the reference's walls
    before fusing (`areamatch merge --non-rigid`; `control_spacing_m`, `bend_length_m` in metres shape
    the warps). Returns a MergeResult; `names` label the maps in its JSON and its picture's legend
    (default "map i"). `threads`: as the `areamatch` program, DEFAULT_THREADS (2); any count gives
    the same result.
    """
    maps = list(maps)
    if not all(isinstance(m, Map) for m in maps):
        raise TypeError("merge: maps must be areamatch.Map objects (for prepared maps call Matcher.merge)")
    matcher = Matcher(door_width_m=door_width_m, allow_reflection=allow_reflection, min_agreement=min_agreement,
                      gate_max_lower_walls=gate_max_lower_walls, gate_min_overlap_m2=gate_min_overlap_m2,
                      min_p_correct=min_p_correct)
    maps = matcher.prepare_all(maps, threads=threads)
    return matcher.merge(maps, reference=reference, resolution=resolution, wall_share=wall_share,
                         max_residual_m=max_residual_m, until_connected=until_connected, same_side=same_side,
                         threads=threads,
                         names=list(names or []), build_merged_map=build_merged_map, non_rigid=non_rigid,
                         control_spacing_m=control_spacing_m, bend_length_m=bend_length_m)


# A pybind11 function's __doc__ opens with its signature; this Python one's does too.
merge.__doc__ = f"merge{_inspect.signature(merge)} -> MergeResult\n\n" + merge.__doc__


__all__ = [
    "DEFAULT_THREADS", "FREE", "OCCUPIED", "UNKNOWN", "Area", "AreaGraph", "Assessment", "Map", "MatchedArea", "Matcher", "MergeResult", "Passage", "Picture",
    "PreparedMap", "Result", "__version__", "assess", "load_map", "match", "merge", "ros", "segment", "synthetic",
]
