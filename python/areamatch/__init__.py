"""areamatch: align 2D occupancy-grid maps of one building and say which room is which.

    import areamatch
    robot = areamatch.load_map("robot.yaml")
    layout = areamatch.load_map("layout.yaml")
    result = areamatch.match(robot, layout)
    if result.ok:
        print(result.T_dest_source)          # 3x3, robot world -> layout world (metres)

Everything is computed by the C++ library (areamatch._core); the GIL is released while maps are
loaded, segmented, matched and merged. Bad input raises ValueError (parameters, file content) or
OSError (files). See docs/python.md.
"""

from ._core import (  # noqa: F401
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
    segment,
)
from . import ros, synthetic  # noqa: F401


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


def _from_dict(key, doc):
    return property(lambda self: self.to_dict()[key], doc=doc)


# The parts of a result that the JSON already spells out are read from it, so the keys and their
# meaning are those of `areamatch match --json` / `merge --json` (docs/cli.md).
Result.evidence = _from_dict("evidence", "How much the maps agree under the result (dict).")
Result.matched_areas = _from_dict("matched_areas", "Room correspondences: source and dest area ids (list of dicts).")
Result.statistics = _from_dict("statistics", "Counts of areas, pairs, hypotheses (dict).")
Result.timings = _from_dict("timings", "Seconds per step (dict).")
Result.margin_different = _from_dict("margin_different", "Margin over the best clearly different transform.")
Result.margin_mirrored = _from_dict("margin_mirrored", "Margin over the best mirrored transform (None without reflection).")
MergeResult.edges = _from_dict("edges", "Every pairwise match run: from, to, ok, p_correct, used, residual_m, note.")
MergeResult.timings = _from_dict("timings", "Seconds per step (dict).")


def merge(maps, *, reference=0, door_width=None, allow_reflection=False, min_agreement=None,
          gate_max_lower_walls=None, gate_min_overlap_m2=None, min_p_correct=None, resolution=None, wall_share=0.5, max_residual=1.0,
          until_connected=False, same_side=True, threads=1, names=None, build_merged_map=True, non_rigid=False,
          control_spacing=None, bend_length=None):
    """Places several maps of one building in the frame of maps[reference] and fuses them.

    As `areamatch merge`: every pair matched (or only until connected), the poses fitted to the
    accepted matches, contradicted matches dropped, unplaced maps reported with a reason.
    `maps`: Map objects, prepared here `threads` at a time (maps prepared already: Matcher.merge).
    `same_side`: refine each accepted match by ICP that pairs walls only with walls facing the
    same way (MergeParams::refine_same_side). `non_rigid`: bend each map onto the reference's walls
    before fusing (`areamatch merge --non-rigid`; `control_spacing`, `bend_length` in metres shape
    the warps). Returns a MergeResult; `names` label the maps in its JSON (default "map i").
    """
    maps = list(maps)
    if not all(isinstance(m, Map) for m in maps):
        raise TypeError("merge: maps must be areamatch.Map objects (for prepared maps call Matcher.merge)")
    matcher = Matcher(door_width=door_width, allow_reflection=allow_reflection, min_agreement=min_agreement,
                      gate_max_lower_walls=gate_max_lower_walls, gate_min_overlap_m2=gate_min_overlap_m2,
                      min_p_correct=min_p_correct)
    maps = matcher.prepare_all(maps, threads=threads)
    return matcher.merge(maps, reference=reference, resolution=resolution, wall_share=wall_share,
                         max_residual=max_residual, until_connected=until_connected, same_side=same_side,
                         threads=threads,
                         names=list(names or []), build_merged_map=build_merged_map, non_rigid=non_rigid,
                         control_spacing=control_spacing, bend_length=bend_length)


__all__ = [
    "FREE", "OCCUPIED", "UNKNOWN", "Area", "AreaGraph", "Assessment", "Map", "Matcher", "MergeResult", "Passage", "Picture",
    "PreparedMap", "Result", "__version__", "assess", "load_map", "match", "merge", "ros", "segment", "synthetic",
]
