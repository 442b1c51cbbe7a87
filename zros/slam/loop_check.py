"""Whether a loop closure match is evidence of a loop, and how much to trust it. Pure numpy.

A loop closure match is the best pose of a new keyframe's scan on a submap of old keyframes,
searched around where the pose graph already puts the keyframe. Two things decide what the
graph should do with it:

1. **Is it strong enough to move the graph?** In a corridor, or a room that looks like the one
   next door, the scan fits in more than one place: the search picks one of them, decimetres
   from the truth, with a fair score (the bighouse's corridor: closures 0.3 to 0.5 m off, scoring
   0.78 to 0.87, matched against a submap whose own keyframes had slid). A right match of the
   same place scores 0.97 to 0.99 (median, house and bighouse, against the simulator's truth),
   and a right closure after drift (the house's east room, 0.15 m) scores as high. So a match
   that moves the keyframe from where the graph puts it by more than the match's own precision
   must score `loop_match_correction_response`; one that confirms the graph (moves it less)
   needs only `loop_match_minimum_response`. The gain of the match over the graph's own pose,
   refined (a likelihood ratio), was measured too and does not tell them apart (false: +0.01
   to +0.10, right after drift: +0.02 to +0.19).
2. **How certain is it?** The refinement's Hessian (points' worth of information per direction,
   zros.slam.matcher) says which directions the scan pins down. The closure's covariance is a
   floor (what right closures are truly off by, `loop_sigma_*`) plus the match's own,
   `match_sigma`² H⁻¹: along a corridor, where H is small, the closure pulls weakly.
"""
from __future__ import annotations

import numpy as np

__all__ = ['closure_information', 'is_ambiguous']

#: Added to the Hessian's diagonal before inverting it (points' worth): a direction with no
#: information gets a covariance of match_sigma² / this, metres, not infinity.
_REGULARISATION = 1e-3


def closure_information(hessian: np.ndarray, floor: np.ndarray, match_sigma: float) -> np.ndarray:
    """(3, 3) information of a loop closure: the inverse of floor⁻¹ + match_sigma² H⁻¹.

    hessian: the match's (3, 3) information in points' worth (MatchResult.information);
    floor: (3, 3) the information a perfect match would still get (from `loop_sigma_*`);
    match_sigma: [m] the likelihood field's spread, the scale of one point's misfit."""
    hessian = np.asarray(hessian, dtype=np.float64)
    hessian = (hessian + hessian.T) / 2.0 + _REGULARISATION * np.eye(3)
    covariance = np.linalg.inv(np.asarray(floor, dtype=np.float64)) + match_sigma ** 2 * np.linalg.inv(hessian)
    information = np.linalg.inv(covariance)
    return (information + information.T) / 2.0


def is_ambiguous(score: float, moved: float, *, min_response: float, tolerance: float) -> bool:
    """Whether a match that moves the keyframe by `moved` [m] from where the graph puts it
    scores too low to be believed (module docstring, 1).

    score: the match's mean likelihood (0..1); min_response: the least score of a match that
    moves the keyframe; tolerance: [m] a move this small is within the match's own precision
    and needs no more than the ordinary loop closure score."""
    return bool(moved > tolerance and score < min_response)
