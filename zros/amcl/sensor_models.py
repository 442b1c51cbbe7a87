"""Laser models: how likely a scan is from each particle's pose, given the map.

Both are nav2_amcl's likelihood-field models, vectorised over particles x beams:

- `LikelihoodFieldModel` (`laser_model_type: likelihood_field`, the default). For each map
  cell, the distance d to the nearest obstacle is precomputed once (an exact Euclidean distance
  transform, capped at `laser_likelihood_max_dist`). Each beam's end point, projected from a
  particle's pose, scores pz = z_hit exp(-d^2 / (2 sigma_hit^2)) + z_rand / range_max (end
  points off the map count as d = max). As in Nav2, a particle's weight is multiplied by
  1 + sum(pz^3) rather than by the product of the pz: the flatter score keeps a filter with
  few particles from collapsing on one bad match.
- `LikelihoodFieldProbModel` (`likelihood_field_prob`): the product of the pz (a sum of logs),
  optionally with beam skipping (`do_beamskip`): beams whose end point lies near an obstacle
  (within `beam_skip_distance`) for fewer than `beam_skip_threshold` of the particles are
  unexplained by the map (people, furniture) and left out, unless that would leave out more
  than `beam_skip_error_threshold` of the beams.

Beams: `max_beams` evenly spaced ones (step (n - 1) // (max_beams - 1), Nav2's integer step);
a beam at or beyond range_max, or NaN, is not used. The laser's mount (x, y, yaw in the base
frame) is composed with each particle's pose. (Spreading `max_beams` over the beams in range
instead, and looking back 8 cells, tracked the house 1.2 cm better on its exact map but lost the
robot on SLAM-made maps where few beams return: docs/benchmarks-history.md, issue 34.)

Walls have a thickness on the map, and a lidar only ever sees their near face. Nav2's field
scores an end point on a wall's far face as a perfect hit, so a particle that stands up to a
wall's thickness too close to it scores as well as the right one: a plateau the cloud drifts on
(12-14 cm along turtlebot3_house's 0.15 m walls). Here (zros's addition) a beam whose end point
lies in a known cell (free or occupied) while one of the `LOOK_BACK` points one, two, ...
cells before it along the beam lies inside an obstacle (an unknown cell, as a wall's inside is
on a map made by a lidar, or an occupied cell with no free neighbour) came out through the
other side: it scores as an end point off the map (the field's maximum distance). An end point
still inside the obstacle keeps the field's score, so a particle a little too close scores as
one a little too far (grazing beams along a face cross no inside and are untouched). The test
is precomputed per map for `DIRECTIONS` beam directions (`emerging_cells`), so it costs one
lookup per beam, not Nav2's ray casting (its `beam` model).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.ndimage import binary_erosion, distance_transform_edt

from zros.amcl.map_grid import MapGrid

__all__ = ['LaserScanData', 'LikelihoodFieldModel', 'LikelihoodFieldProbModel', 'create_laser_model',
           'LASER_MODELS', 'LOOK_BACK', 'DIRECTIONS', 'distance_field', 'emerging_cells']

#: [cells] How far back from a beam's end point to look for an obstacle's inside: a wall three
#: cells thick (turtlebot3_house's 0.15 m at 0.05 m) is caught from its far face and the cell past it.
#: A beam meeting the wall at an angle b reaches only 3 sin(b) cells into it (1-1.5 at 20-30 deg),
#: so such a beam just past the far face still scores as a hit. Looking back 8 cells over 32
#: directions caught it and tracked the house better on its exact map, but navigation on the
#: SLAM-made map lost the robot where few beams return (docs/benchmarks-history.md, issue 34).
LOOK_BACK = 3
#: Beam directions the look-back is precomputed for (one bit each of a uint16 per cell): 22.5 deg
#: apart, so a look-back point is at most 3 cells x sin(11.25 deg) = 0.6 cell off the beam.
DIRECTIONS = 16


class LaserScanData(NamedTuple):
    """One scan, prepared as Nav2 prepares it: ranges [m] with readings at or below range_min
    already moved to range_max (so they are ignored), bearings [rad] in the laser frame."""
    ranges: np.ndarray
    bearings: np.ndarray
    range_max: float


def distance_field(grid: MapGrid, max_dist: float) -> np.ndarray:
    """Distance [m] from each cell's centre to the nearest occupied cell's centre, capped at
    `max_dist`: (height, width) float64. A map without obstacles is `max_dist` everywhere."""
    if not grid.occupied.any():
        return np.full(grid.data.shape, float(max_dist))
    return np.minimum(distance_transform_edt(~grid.occupied) * grid.resolution, max_dist)


def emerging_cells(grid: MapGrid) -> np.ndarray:
    """Per cell (height, width) uint16: bit d is set when a beam ending in this known cell in
    direction d x 360/DIRECTIONS deg came out of an obstacle's inside (one of the LOOK_BACK cells
    before it, along that direction, is unknown or occupied with no free neighbour). Computed
    once per map, so scoring a beam costs one lookup instead of LOOK_BACK."""
    opaque = (grid.data < 0) | binary_erosion(grid.occupied)
    known = grid.data >= 0
    bits = np.zeros(grid.data.shape, dtype=np.uint16)
    height, width = opaque.shape
    for d in range(DIRECTIONS):
        angle = 2.0 * np.pi * d / DIRECTIONS
        behind = np.zeros_like(opaque)
        for steps in range(1, LOOK_BACK + 1):
            dc, dr = int(round(steps * np.cos(angle))), int(round(steps * np.sin(angle)))
            if abs(dr) >= height or abs(dc) >= width:
                continue                      # no cell that far back is on the map (nor are the slices)
            # behind[r, c] |= opaque[r - dr, c - dc], where that cell is on the map
            behind[max(dr, 0):height + min(dr, 0), max(dc, 0):width + min(dc, 0)] |= \
                opaque[max(-dr, 0):height - max(dr, 0), max(-dc, 0):width - max(dc, 0)]
        bits |= (known & behind).astype(np.uint16) << np.uint16(d)
    return bits


class LikelihoodFieldModel:
    """The likelihood-field laser model (see the module docstring)."""

    def __init__(self, grid: MapGrid, *, z_hit: float, z_rand: float, sigma_hit: float, max_dist: float,
                 max_beams: int) -> None:
        if max_beams < 2:
            raise ValueError(f'max_beams must be >= 2, got {max_beams}')
        if not sigma_hit > 0:
            raise ValueError(f'sigma_hit must be > 0 [m], got {sigma_hit}')
        self.grid = grid
        self.z_hit, self.z_rand, self.sigma_hit = z_hit, z_rand, sigma_hit
        self.max_dist, self.max_beams = float(max_dist), int(max_beams)
        # Flat per-cell tables with a border of one "off the map" cell on every side: an end point
        # clipped into the padded grid lands on the border when it is off the map, so no separate
        # inside test is needed per beam.
        self._stride = grid.width + 2
        self._distance = np.pad(distance_field(grid, self.max_dist), 1, constant_values=self.max_dist).ravel()
        self._emerges = np.pad(emerging_cells(grid), 1, constant_values=0).ravel()
        self._scores: dict[float, tuple[np.ndarray, float]] = {}

    def _pz(self, distance: np.ndarray | float, range_max: float) -> np.ndarray | float:
        return self.z_hit * np.exp(-(np.square(distance)) / (2.0 * self.sigma_hit ** 2)) + self.z_rand / range_max

    def _beam_score(self, pz: np.ndarray | float) -> np.ndarray | float:
        """What one beam adds to a particle's score: pz^3 here, summed (see `_score`)."""
        return pz ** 3

    def _score_table(self, range_max: float) -> tuple[np.ndarray, float]:
        """Per padded cell, a beam's score when it ends there, and the score of a beam that ended
        off the map or came out through an obstacle. An end point's score depends only on its
        cell, so it is computed once per cell (and scan range) rather than per particle and beam."""
        table = self._scores.get(range_max)
        if table is None:
            table = self._scores[range_max] = (self._beam_score(self._pz(self._distance, range_max)),
                                               float(self._beam_score(self._pz(self.max_dist, range_max))))
        return table

    def beams(self, scan: LaserScanData) -> tuple[np.ndarray, np.ndarray]:
        """The ranges and bearings of the beams used: sub-sampled, valid ones only."""
        step = max((len(scan.ranges) - 1) // (self.max_beams - 1), 1)
        ranges, bearings = scan.ranges[::step], scan.bearings[::step]
        valid = np.isfinite(ranges) & (ranges < scan.range_max)
        return ranges[valid], bearings[valid]

    def _end_cells(self, particles: np.ndarray, ranges: np.ndarray, bearings: np.ndarray,
                   laser_pose: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
        """Where each beam ends, cast from each particle: (cells, emerged), both (N, B): the flat
        index into the padded tables, and whether the beam came out through an obstacle (the
        module docstring). Computed in cell units, so the map's offset and scale are applied
        once per particle and beam rather than per end point."""
        lx, ly, lyaw = laser_pose
        resolution, (ox, oy) = self.grid.resolution, self.grid.origin
        cos_p, sin_p = np.cos(particles[:, 2]), np.sin(particles[:, 2])
        sx = (particles[:, 0] + lx * cos_p - ly * sin_p - ox) / resolution + 1.0     # + 1: the border
        sy = (particles[:, 1] + lx * sin_p + ly * cos_p - oy) / resolution + 1.0
        cos_s, sin_s = np.cos(particles[:, 2] + lyaw)[:, None], np.sin(particles[:, 2] + lyaw)[:, None]
        rc, rs = ranges * np.cos(bearings) / resolution, ranges * np.sin(bearings) / resolution
        cols = cos_s * rc
        cols -= sin_s * rs
        cols += sx[:, None]
        rows = sin_s * rc
        rows += cos_s * rs
        rows += sy[:, None]
        np.clip(cols, 0.0, self._stride - 1, out=cols)          # off the map: onto the border
        np.clip(rows, 0.0, self.grid.height + 1, out=rows)
        cells = rows.astype(np.intp)                              # non-negative: truncation is floor
        cells *= self._stride
        cells += cols.astype(np.intp)
        # The beam's direction, rounded to one of DIRECTIONS (a power of two, so & wraps it); the
        # whole turns added keep the sum positive, so truncation rounds as floor would.
        turns = DIRECTIONS / (2.0 * np.pi)
        direction = ((particles[:, 2] + lyaw) * turns + (0.5 + 8 * DIRECTIONS))[:, None] + bearings * turns
        emerged = (self._emerges[cells] >> (direction.astype(np.intp) & (DIRECTIONS - 1))) & 1
        return cells, emerged.astype(bool)

    def end_distances(self, particles: np.ndarray, ranges: np.ndarray, bearings: np.ndarray,
                      laser_pose: tuple[float, float, float]) -> np.ndarray:
        """The distance [m] (N, B) each beam's end point, cast from each particle, scores with:
        the field's value there, the maximum off the map or when the beam came out through an
        obstacle (the module docstring)."""
        cells, emerged = self._end_cells(particles, ranges, bearings, laser_pose)
        return np.where(emerged, self.max_dist, self._distance[cells])

    def explained_share(self, pose: np.ndarray, scan: LaserScanData, laser_pose: tuple[float, float, float], *,
                        within: float) -> float:
        """The share of the used beams whose end point, cast from `pose` (x, y, yaw), lies within
        `within` [m] of an obstacle on the map (nan when no beam is used). The filter's spread
        says how sure it is among the poses it kept; this says whether the map agrees with the
        scan there at all (a cloud collapsed on the wrong pillar row scores about half)."""
        return float(self.weigh(np.asarray(pose, dtype=np.float64)[None, :], scan, laser_pose, within=within)[1][0])

    def likelihood(self, particles: np.ndarray, scan: LaserScanData,
                   laser_pose: tuple[float, float, float]) -> np.ndarray:
        """The factor (N,) to multiply each particle's weight by for this scan."""
        return self.weigh(particles, scan, laser_pose, within=None)[0]

    def weigh(self, particles: np.ndarray, scan: LaserScanData, laser_pose: tuple[float, float, float], *,
              within: float | None) -> tuple[np.ndarray, np.ndarray | None]:
        """`likelihood`'s factors (N,) and, from the same end points, the share (N,) of each
        particle's beams the map explains (`explained_share`'s, nan when no beam is used);
        `within` None skips the share (None), which saves a pass over every end point."""
        ranges, bearings = self.beams(scan)
        if len(ranges) == 0:
            return np.ones(len(particles)), None if within is None else np.full(len(particles), np.nan)
        cells, emerged = self._end_cells(particles, ranges, bearings, laser_pose)
        distance = None
        if within is not None or self._needs_distance():
            distance = np.where(emerged, self.max_dist, self._distance[cells])
        scores, far = self._score_table(float(scan.range_max))
        beam_scores = np.where(emerged, far, scores[cells])
        explained = None if within is None else np.mean(distance < within, axis=1)
        return self._score(beam_scores, distance), explained

    def _needs_distance(self) -> bool:
        """Whether `_score` needs the end points' distances (beam skipping does)."""
        return False

    def _score(self, beam_scores: np.ndarray, distance: np.ndarray | None) -> np.ndarray:
        """Each particle's factor from its beams' scores (N, B), `_beam_score` of their pz."""
        return 1.0 + np.sum(beam_scores, axis=1)


class LikelihoodFieldProbModel(LikelihoodFieldModel):
    """The product form of the likelihood field, with optional beam skipping."""

    def __init__(self, grid: MapGrid, *, z_hit: float, z_rand: float, sigma_hit: float, max_dist: float,
                 max_beams: int, do_beamskip: bool = False, beam_skip_distance: float = 0.5,
                 beam_skip_threshold: float = 0.3, beam_skip_error_threshold: float = 0.9) -> None:
        super().__init__(grid, z_hit=z_hit, z_rand=z_rand, sigma_hit=sigma_hit, max_dist=max_dist,
                         max_beams=max_beams)
        self.do_beamskip = do_beamskip
        self.beam_skip_distance = beam_skip_distance
        self.beam_skip_threshold = beam_skip_threshold
        self.beam_skip_error_threshold = beam_skip_error_threshold

    def _beam_score(self, pz: np.ndarray | float) -> np.ndarray | float:
        """log pz: the product of the beams' pz is the exp of the sum."""
        return np.log(pz)

    def _needs_distance(self) -> bool:
        return self.do_beamskip

    def _score(self, beam_scores: np.ndarray, distance: np.ndarray | None) -> np.ndarray:
        if self.do_beamskip:
            explained = (distance < self.beam_skip_distance).mean(axis=0) > self.beam_skip_threshold
            skipped = np.count_nonzero(~explained)
            if skipped < distance.shape[1] * self.beam_skip_error_threshold:
                beam_scores = beam_scores[:, explained]
        return np.exp(beam_scores.sum(axis=1))


#: `laser_model_type` values. Nav2's `beam` model (ray casting from every particle) is not provided.
LASER_MODELS = ('likelihood_field', 'likelihood_field_prob')


def create_laser_model(laser_model_type: str, grid: MapGrid, *, z_hit: float, z_rand: float, sigma_hit: float,
                       max_dist: float, max_beams: int, do_beamskip: bool = False, beam_skip_distance: float = 0.5,
                       beam_skip_threshold: float = 0.3,
                       beam_skip_error_threshold: float = 0.9) -> LikelihoodFieldModel:
    """The laser model named by `laser_model_type`; ValueError for another name."""
    common = dict(z_hit=z_hit, z_rand=z_rand, sigma_hit=sigma_hit, max_dist=max_dist, max_beams=max_beams)
    if laser_model_type == 'likelihood_field':
        return LikelihoodFieldModel(grid, **common)
    if laser_model_type == 'likelihood_field_prob':
        return LikelihoodFieldProbModel(grid, **common, do_beamskip=do_beamskip,
                                        beam_skip_distance=beam_skip_distance, beam_skip_threshold=beam_skip_threshold,
                                        beam_skip_error_threshold=beam_skip_error_threshold)
    raise ValueError(f"laser_model_type '{laser_model_type}' is not supported (supported: {', '.join(LASER_MODELS)})")

