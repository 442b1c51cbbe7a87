"""The particle filter of AMCL: particle set, weights, KLD-adaptive resampling, recovery, estimate.

After nav2_amcl's pf/ (Fox, "Adapting the sample size in particle filters through
KLD-sampling", IJRR 2003; Thrun, Burgard, Fox, Probabilistic Robotics, ch. 4 and 8), with
numpy over the whole set instead of a loop per particle:

- Initialisation: `init_gaussian` (an initial pose and its covariance) or `init_uniform`
  (global localization: poses uniform over the map's free space), `max_particles` of them.
  Unlike Nav2, a Gaussian that mostly falls outside free space (an initial pose with a
  covariance of hundreds of m^2, or next to walls) is drawn over the free cells, weighted by
  its density, instead of off the map where no scan can ever match.
- `sensor_update`: weights times the laser model's likelihood, normalised; a measure of fit
  feeds the slow and fast running averages (`recovery_alpha_slow`, `recovery_alpha_fast`):
  Nav2's average weight by default, a share of beams explained from the localizer
  (zros.amcl.localizer.Amcl._fit says which and why).
- `resample`: the new set's size comes from KLD sampling: samples are drawn one after another
  and counted in 0.5 m x 0.5 m x 10 deg bins; the set is big enough once it exceeds
  (k - 1) / (2 pf_err) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) pf_z)^3 for k occupied bins,
  clamped to [min_particles, max_particles] (pf_z is used as the quantile, as Nav2 does). The
  counting runs on one vectorised draw of max_particles candidates (the first n of a random
  draw are a random draw of n); the kept set is then drawn with low-variance (systematic)
  resampling. With recovery on, each new particle is replaced by a random free-space pose with
  probability max(0, 1 - w_fast / w_slow); as in Nav2 the random ones count in the bins, so a
  filter that injects many grows towards max_particles. Unlike Nav2, the averages are not
  restarted after an injection (Probabilistic Robotics' Augmented MCL): Nav2's restart puts
  w_slow at the lost level, so it injects once and never again while the robot stays lost.
- `estimate`: particles clustered by connected occupied bins (yaw wraps around); the pose is
  the heaviest cluster's weighted mean (circular mean for yaw), the covariance the whole set's
  (x, y and their cross term; yaw as -2 ln of the mean resultant length), as Nav2 publishes.

Poses are (N, 3) x, y [m], yaw [rad, in [-pi, pi)].
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.ndimage import label
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from zros.amcl.map_grid import MapGrid
from zros.amcl.motion_models import MotionModel
from zros.rotations import wrap_angle

__all__ = ['ParticleFilter', 'PoseEstimate', 'KLD_BIN', 'kld_limit']

#: Histogram bin for KLD sampling and clustering: x [m], y [m], yaw [rad] (Nav2's).
KLD_BIN = (0.5, 0.5, math.radians(10.0))
_YAW_BINS = int(round(2.0 * math.pi / KLD_BIN[2]))
#: Share of an initial Gaussian's samples that must fall in free space to keep it as drawn.
_FREE_SHARE = 0.5
_REDRAW_ROUNDS = 5


class PoseEstimate(NamedTuple):
    """The filter's answer: `pose` (3,) x, y, yaw of the heaviest cluster; `covariance` (3, 3)
    of the whole set (widened by the localizer when the scan does not fit, zros.amcl.localizer);
    `weight` the heaviest cluster's share; `clusters` how many there are; `explained` the share
    of beams the map explains at `pose` (nan until the localizer sets it)."""
    pose: np.ndarray
    covariance: np.ndarray
    weight: float
    clusters: int
    explained: float = math.nan


def kld_limit(k: np.ndarray, *, pf_err: float, pf_z: float, min_particles: int, max_particles: int) -> np.ndarray:
    """How many particles KLD sampling wants for k (array) occupied bins (max for k <= 1, as Nav2)."""
    k = np.asarray(k, dtype=np.float64)
    limit = np.full(k.shape, float(max_particles))
    many = k > 1
    b = 2.0 / (9.0 * (k[many] - 1.0))
    x = 1.0 - b + np.sqrt(b) * pf_z
    limit[many] = np.clip(np.ceil((k[many] - 1.0) / (2.0 * pf_err) * x ** 3), min_particles, max_particles)
    return limit


def bins(poses: np.ndarray) -> np.ndarray:
    """Integer histogram bins (N, 3) of poses; the yaw bin is in [0, 36)."""
    keys = np.empty((len(poses), 3), dtype=np.int64)
    keys[:, 0] = np.floor(poses[:, 0] / KLD_BIN[0])
    keys[:, 1] = np.floor(poses[:, 1] / KLD_BIN[1])
    keys[:, 2] = np.floor((wrap_angle(poses[:, 2]) + math.pi) / KLD_BIN[2]).clip(0, _YAW_BINS - 1)
    return keys


def _bin_ids(keys: np.ndarray) -> np.ndarray:
    """One int64 per bin (N,), equal iff the bins are."""
    low = keys.min(axis=0)
    span = keys.max(axis=0) - low + 1
    shifted = keys - low
    return (shifted[:, 0] * span[1] + shifted[:, 1]) * span[2] + shifted[:, 2]


class ParticleFilter:
    """A particle set over a map. See the module docstring. Not thread-safe.

    Args:
        grid: the map (free space for initialisation and recovery).
        min_particles, max_particles: bounds of the adaptive set size.
        pf_err, pf_z: KLD sampling's error bound and quantile.
        alpha_slow, alpha_fast: decay rates of the weight averages (0, 0: no recovery).
        rng: the random generator (seed it for repeatable runs).
    """

    def __init__(self, grid: MapGrid, *, min_particles: int = 500, max_particles: int = 2000, pf_err: float = 0.05,
                 pf_z: float = 0.99, alpha_slow: float = 0.0, alpha_fast: float = 0.0,
                 rng: np.random.Generator | None = None) -> None:
        if not 1 <= min_particles <= max_particles:
            raise ValueError(f'need 1 <= min_particles <= max_particles, got {min_particles} and {max_particles}')
        if not pf_err > 0:
            raise ValueError(f'pf_err must be > 0, got {pf_err}')
        self.grid = grid
        self.min_particles, self.max_particles = int(min_particles), int(max_particles)
        self.pf_err, self.pf_z = pf_err, pf_z
        self.alpha_slow, self.alpha_fast = alpha_slow, alpha_fast
        self.rng = rng or np.random.default_rng()
        self.particles = np.zeros((0, 3))
        self.weights = np.zeros(0)
        self.w_slow = self.w_fast = 0.0

    def __len__(self) -> int:
        return len(self.particles)

    def _reset(self, particles: np.ndarray) -> None:
        particles[:, 2] = wrap_angle(particles[:, 2])
        self.particles = particles
        self.weights = np.full(len(particles), 1.0 / len(particles))
        self.w_slow = self.w_fast = 0.0

    # -- initialisation ---------------------------------------------------------------------------
    def init_uniform(self) -> None:
        """Global localization: max_particles poses uniform over the free space."""
        self._reset(self.grid.sample_free(self.max_particles, self.rng))

    def init_gaussian(self, mean: np.ndarray, covariance: np.ndarray) -> bool:
        """max_particles poses around `mean` (3,) with `covariance` (3, 3), kept in free space
        (see the module docstring). Returns False when none of the Gaussian falls in free space:
        the particles are then drawn as asked, wherever that is."""
        mean = np.asarray(mean, dtype=np.float64)
        covariance = (np.asarray(covariance, dtype=np.float64) + np.asarray(covariance).T) / 2.0
        draw = _gaussian_sampler(mean, covariance, self.rng)
        particles = draw(self.max_particles)
        free = self.grid.is_free(particles[:, 0], particles[:, 1])
        share = free.mean()
        if share == 0.0:
            self._reset(particles)
            return False
        if share >= _FREE_SHARE:
            for _ in range(_REDRAW_ROUNDS):
                if free.all():
                    break
                missing = np.flatnonzero(~free)
                particles[missing] = draw(len(missing))
                free[missing] = self.grid.is_free(particles[missing, 0], particles[missing, 1])
            missing = np.flatnonzero(~free)
            if len(missing):
                particles[missing] = particles[self.rng.choice(np.flatnonzero(free), len(missing))]
        else:
            particles = self._free_cells_under(mean, covariance)
        self._reset(particles)
        return True

    def _free_cells_under(self, mean: np.ndarray, covariance: np.ndarray) -> np.ndarray:
        """max_particles poses in free cells, drawn by the Gaussian's x-y density at each cell
        (plus the cell's own spread, so a narrow Gaussian keeps finite weights)."""
        x, y = self.grid.cell_centres(self.grid.free_cells)
        spread = covariance[:2, :2] + np.eye(2) * self.grid.resolution ** 2 / 12.0
        offsets = np.column_stack([x - mean[0], y - mean[1]])
        mahalanobis = np.einsum('ij,jk,ik->i', offsets, np.linalg.pinv(spread), offsets)
        weights = np.exp(-0.5 * (mahalanobis - mahalanobis.min()))
        particles = self.grid.sample_free(self.max_particles, self.rng, weights)
        yaw_sigma = math.sqrt(max(covariance[2, 2], 0.0))
        particles[:, 2] = mean[2] + yaw_sigma * self.rng.standard_normal(self.max_particles)
        return particles

    # -- the filter's steps ---------------------------------------------------------------------------
    def motion_update(self, model: MotionModel, pose: np.ndarray, delta: np.ndarray) -> None:
        """Move every particle by the odometry increment `delta` that ended at `pose`."""
        model.odometry_update(self.particles, np.asarray(pose, dtype=np.float64),
                              np.asarray(delta, dtype=np.float64), self.rng)

    def sensor_update(self, likelihood: np.ndarray, *, fit: float | None = None) -> None:
        """Weight the particles by `likelihood` (N,) and update the recovery averages with `fit`,
        how well the scan matched (default Nav2's: the weighted likelihood over N; nan: leave
        the averages as they are)."""
        weights = self.weights * likelihood
        total = float(weights.sum())
        if not (total > 0.0 and math.isfinite(total)):
            self.weights = np.full(len(self.particles), 1.0 / len(self.particles))
            return
        self.weights = weights / total
        average = total / len(weights) if fit is None else fit
        if math.isnan(average):
            return
        self.w_slow = average if self.w_slow == 0.0 else self.w_slow + self.alpha_slow * (average - self.w_slow)
        self.w_fast = average if self.w_fast == 0.0 else self.w_fast + self.alpha_fast * (average - self.w_fast)

    def resample(self) -> None:
        """A new set, sized by KLD sampling, drawn by low-variance resampling (+ recovery)."""
        cumulative = np.cumsum(self.weights)
        total = cumulative[-1]
        last = len(cumulative) - 1
        candidates = self.particles[np.minimum(np.searchsorted(cumulative, self.rng.random(self.max_particles) * total,
                                                               side='right'), last)]
        w_diff = 1.0 - self.w_fast / self.w_slow if self.w_slow > 0.0 else 0.0
        fresh = self.rng.random(self.max_particles) < w_diff if len(self.grid.free_cells) else np.zeros(0, bool)
        if fresh.any():
            candidates[fresh] = self.grid.sample_free(int(np.count_nonzero(fresh)), self.rng)
        count = self._kld_count(candidates)
        positions = (self.rng.random() + np.arange(count)) * (total / count)
        chosen = np.minimum(np.searchsorted(cumulative, positions, side='right'), last)
        particles = self.particles[chosen]
        if fresh.any():
            particles[fresh[:count]] = candidates[:count][fresh[:count]]
        self.particles = particles
        self.weights = np.full(count, 1.0 / count)

    def _kld_count(self, draws: np.ndarray) -> int:
        """The set size KLD sampling settles on when the samples come in the order of `draws`."""
        ids = _bin_ids(bins(draws))
        new_bin = np.zeros(len(ids), dtype=bool)
        new_bin[np.unique(ids, return_index=True)[1]] = True
        occupied = np.cumsum(new_bin)
        limit = kld_limit(occupied, pf_err=self.pf_err, pf_z=self.pf_z, min_particles=self.min_particles,
                          max_particles=self.max_particles)
        enough = np.flatnonzero(np.arange(1, len(ids) + 1) > limit)
        return int(enough[0] + 1) if len(enough) else len(ids)

    # -- the answer ----------------------------------------------------------------------------
    def estimate(self) -> PoseEstimate:
        """The heaviest cluster's mean and the set's covariance (see the module docstring)."""
        particles, weights = self.particles, self.weights / self.weights.sum()
        cluster = self._clusters(particles)
        cluster_weight = np.bincount(cluster, weights=weights)
        best = int(np.argmax(cluster_weight))
        members = cluster == best
        w = weights[members] / cluster_weight[best]
        p = particles[members]
        yaw = math.atan2(float(w @ np.sin(p[:, 2])), float(w @ np.cos(p[:, 2])))
        pose = np.array([w @ p[:, 0], w @ p[:, 1], yaw])

        mean_xy = weights @ particles[:, :2]
        centred = particles[:, :2] - mean_xy
        covariance = np.zeros((3, 3))
        covariance[:2, :2] = (centred * weights[:, None]).T @ centred
        resultant = math.hypot(float(weights @ np.sin(particles[:, 2])), float(weights @ np.cos(particles[:, 2])))
        covariance[2, 2] = -2.0 * math.log(max(resultant, 1e-300))
        return PoseEstimate(pose, covariance, float(cluster_weight[best]), int(np.count_nonzero(cluster_weight)))

    @staticmethod
    def _clusters(particles: np.ndarray) -> np.ndarray:
        """Cluster id (N,) per particle: particles in touching occupied bins share one."""
        keys = bins(particles)
        keys[:, :2] -= keys[:, :2].min(axis=0)
        size = (*(keys[:, :2].max(axis=0) + 1), _YAW_BINS + 1)
        occupied = np.zeros(size, dtype=bool)
        occupied[keys[:, 0], keys[:, 1], keys[:, 2]] = True
        occupied[:, :, _YAW_BINS] = occupied[:, :, 0]       # yaw wraps: the last bin touches the first
        labels, count = label(occupied, structure=np.ones((3, 3, 3), dtype=bool))
        wrapped = occupied[:, :, 0]
        links = coo_matrix((np.ones(np.count_nonzero(wrapped)), (labels[:, :, 0][wrapped],
                                                                 labels[:, :, _YAW_BINS][wrapped])),
                           shape=(count + 1, count + 1))
        _, component = connected_components(links, directed=False)
        return component[labels[keys[:, 0], keys[:, 1], keys[:, 2]]]


def _gaussian_sampler(mean: np.ndarray, covariance: np.ndarray, rng: np.random.Generator):
    """A function n -> (n, 3) samples of the Gaussian (a singular covariance is fine)."""
    values, vectors = np.linalg.eigh(covariance)
    scale = vectors * np.sqrt(np.clip(values, 0.0, None))

    def draw(count: int) -> np.ndarray:
        samples = mean + rng.standard_normal((count, 3)) @ scale.T
        samples[:, 2] = wrap_angle(samples[:, 2])
        return samples
    return draw
