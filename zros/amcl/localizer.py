"""AMCL's update cycle without the middleware: when to filter, what to publish, map -> odom.

`Amcl` is what nav2_amcl's node does with each scan, minus topics and TF (the `nav2_amcl amcl`
node and benchmarks/localization.py both drive it):

1. Nothing happens until the pose is known: `set_initial_pose` or `global_localization`.
2. The first scan after that updates the filter without motion and publishes.
3. Afterwards the filter runs only once odometry has moved `update_min_d` in x or y, or turned
   `update_min_a` (or after `request_nomotion_update`): motion model, laser model, and every
   `resample_interval` updates a resampling, which publishes a new estimate.
   A scan none of whose beams is used (all beyond range_max, NaN or too close: a robot more than
   the lidar's range from anything) moves the particles but neither weighs nor resamples them
   nor publishes (zros's choice; Nav2 weighs every particle by 1, resamples and publishes). It
   says nothing, and Nav2's estimate then is the mean of a cloud the motion model alone spreads:
   with alphas of 0.2 that mean falls behind the robot (a spread in heading shortens every
   particle's progress along the way; 25 cm in 2 m in turtlebot3_house), while the last
   estimate carried by odometry (the map -> odom transform kept) follows the robot.
4. `map_to_odom()` turns the estimate into the map -> odom transform, using the odometry pose
   of the scan the estimate came from.

Scans are prepared as Nav2 prepares them (`prepare_scan`): range_max is the scan's, or
`laser_max_range` when that is positive and smaller; range_min likewise with `laser_min_range`;
a reading at or below range_min (including -inf, "too close") counts as range_max, which the
laser model ignores, as it ignores NaN.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, NamedTuple

import numpy as np

from zros.amcl.map_grid import MapGrid
from zros.amcl.motion_models import create_motion_model
from zros.amcl.particle_filter import ParticleFilter, PoseEstimate
from zros.amcl.sensor_models import LaserScanData, create_laser_model
from zros.rotations import angle_diff

__all__ = ['Amcl', 'AmclParameters', 'LaserScanData', 'UpdateResult', 'compose', 'inverse', 'honest_covariance',
           'confirmation', 'FIT_DISTANCE', 'FIT_SHARE', 'LOST_VARIANCE', 'LOST_SHARE',
           'CONFIRM_ESTIMATES', 'CONFIRM_SHARE']

#: [m] a beam is explained by the map when its end point lies this close to an obstacle.
FIT_DISTANCE = 0.1
#: Share of explained beams at or above which the particle set's own spread is believed. Measured
#: in turtlebot3_world (benchmarks/localization.py): a right pose explains 1.0 of them in the
#: median and over 0.99 in 19 estimates of 20; the clouds global localization settled 2.6 m off
#: explained 0.77-0.85, one a pillar row off about half.
FIT_SHARE = 0.95
#: [m^2] position variance reported when no beam is explained; in between, in proportion.
LOST_VARIANCE = 1.0
#: Share of explained beams under which an estimate means the filter lost the robot (right poses
#: never went below 0.77 in turtlebot3_world).
LOST_SHARE = 0.5
#: After a lost estimate (or global localization), the position variance is reported no smaller
#: than a lost estimate's until CONFIRM_ESTIMATES estimates in a row explain CONFIRM_SHARE of the
#: beams. A cloud that wandered from a lost place onto turtlebot3_world's near twin (the world is
#: 87 % the same turned half a turn) explains 0.94-0.98 of the beams for 10-15 s at a time, as
#: much as a right pose in single scans; only a right pose keeps explaining nearly all of them.
CONFIRM_ESTIMATES = 10
CONFIRM_SHARE = 0.99


@dataclass
class AmclParameters:
    """The filter's tunables, with nav2_amcl's names and Humble defaults (units: m, rad)."""
    alpha1: float = 0.2
    alpha2: float = 0.2
    alpha3: float = 0.2
    alpha4: float = 0.2
    alpha5: float = 0.2
    beam_skip_distance: float = 0.5
    beam_skip_error_threshold: float = 0.9
    beam_skip_threshold: float = 0.3
    do_beamskip: bool = False
    laser_likelihood_max_dist: float = 2.0
    laser_max_range: float = 100.0
    laser_min_range: float = -1.0
    laser_model_type: str = 'likelihood_field'
    max_beams: int = 60
    max_particles: int = 2000
    min_particles: int = 500
    pf_err: float = 0.05
    pf_z: float = 0.99
    recovery_alpha_fast: float = 0.0
    recovery_alpha_slow: float = 0.0
    resample_interval: int = 1
    robot_model_type: str = 'nav2_amcl::DifferentialMotionModel'
    sigma_hit: float = 0.2
    update_min_a: float = 0.2
    update_min_d: float = 0.25
    z_hit: float = 0.5
    z_rand: float = 0.5

    @classmethod
    def from_parameters(cls, values: Mapping[str, object]) -> AmclParameters:
        """The tunables named in `values` (an `amcl:` section's ros__parameters; other names are
        ignored), each cast to its field's type; the others keep their defaults."""
        defaults = cls()
        return cls(**{name: type(default)(values[name]) for name, default in vars(defaults).items() if name in values})


class UpdateResult(NamedTuple):
    """What one scan did: `updated` the filter ran; `resampled`; `published` there is a new
    estimate to publish (amcl_pose, map -> odom); `estimate` the latest one (None before any)."""
    updated: bool
    resampled: bool
    published: bool
    estimate: PoseEstimate | None


def compose(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The 2D pose b expressed in a's parent frame (a then b)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array([a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], angle_diff(a[2] + b[2], 0.0)])


def inverse(a: np.ndarray) -> np.ndarray:
    """The inverse of the 2D transform a."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array([-c * a[0] - s * a[1], s * a[0] - c * a[1], angle_diff(-a[2], 0.0)])


def honest_covariance(covariance: np.ndarray, explained: float) -> np.ndarray:
    """`covariance` (3, 3), its position part widened when the scan does not fit the estimate.

    A particle set that collapsed on a wrong pose (a symmetric world after global localization,
    a kidnapped robot without recovery) has a small spread and would be reported as confident,
    as Nav2's AMCL reports it. Here the larger position variance is raised, isotropically, to at
    least LOST_VARIANCE * (FIT_SHARE - explained) / FIT_SHARE when fewer than FIT_SHARE of the
    beams are explained (zros's addition; a right pose keeps Nav2's covariance unchanged).
    """
    if not explained < FIT_SHARE:          # also nan: no beams, nothing to judge by
        return covariance
    floor = LOST_VARIANCE * (FIT_SHARE - explained) / FIT_SHARE
    widened = np.array(covariance, dtype=np.float64)
    largest = float(np.linalg.eigvalsh(widened[:2, :2])[-1])
    if largest < floor:
        widened[:2, :2] += np.eye(2) * (floor - largest)
    return widened


def confirmation(unconfirmed: int | None, explained: float) -> int | None:
    """The next state of the check above: None when the estimate is believed, else how many
    estimates in a row have explained CONFIRM_SHARE of the beams since the robot was lost.
    `explained` nan (no beam used) changes nothing."""
    if explained < LOST_SHARE:
        return 0
    if unconfirmed is None or math.isnan(explained):
        return unconfirmed
    unconfirmed = unconfirmed + 1 if explained >= CONFIRM_SHARE else 0
    return None if unconfirmed >= CONFIRM_ESTIMATES else unconfirmed


class Amcl:
    """One robot's localizer on one map. See the module docstring.

    Args:
        parameters: the tunables.
        grid: the map.
        seed: seeds the filter's random numbers (None: fresh entropy).

    Raises:
        ValueError: a parameter out of range or an unknown model name (the message names it).
    """

    def __init__(self, parameters: AmclParameters, grid: MapGrid, *, seed: int | None = None) -> None:
        p = self.parameters = parameters
        if p.resample_interval < 1:
            raise ValueError(f'resample_interval must be >= 1, got {p.resample_interval}')
        self.motion_model = create_motion_model(p.robot_model_type, (p.alpha1, p.alpha2, p.alpha3, p.alpha4, p.alpha5))
        self.pf = ParticleFilter(grid, min_particles=p.min_particles, max_particles=p.max_particles, pf_err=p.pf_err,
                                 pf_z=p.pf_z, alpha_slow=p.recovery_alpha_slow, alpha_fast=p.recovery_alpha_fast,
                                 rng=np.random.default_rng(seed))
        #: Recovery by random particles is on (Nav2: either decay rate above 0).
        self._recovery = p.recovery_alpha_slow > 0.0 or p.recovery_alpha_fast > 0.0
        self.set_map(grid)
        self.pose_known = False
        self.estimate: PoseEstimate | None = None
        self._odom_pose: np.ndarray | None = None      # odometry at the last filter update
        self._estimate_odom_pose: np.ndarray | None = None
        self._force_update = False
        self._updates = 0
        self._unconfirmed: int | None = None       # see confirmation()

    @property
    def grid(self) -> MapGrid:
        return self.pf.grid

    def set_map(self, grid: MapGrid) -> None:
        """Localize in `grid` from now on (the particles stay where they are)."""
        p = self.parameters
        self.laser_model = create_laser_model(
            p.laser_model_type, grid, z_hit=p.z_hit, z_rand=p.z_rand, sigma_hit=p.sigma_hit,
            max_dist=p.laser_likelihood_max_dist, max_beams=p.max_beams, do_beamskip=p.do_beamskip,
            beam_skip_distance=p.beam_skip_distance, beam_skip_threshold=p.beam_skip_threshold,
            beam_skip_error_threshold=p.beam_skip_error_threshold)
        self.pf.grid = grid

    # -- where to start ------------------------------------------------------------------------------
    def set_initial_pose(self, pose: tuple[float, float, float], covariance: np.ndarray) -> bool:
        """Restart the filter around `pose` (x, y, yaw) with `covariance` (3, 3). Returns False
        when the pose and its spread lie wholly outside the map's free space (it is used anyway)."""
        in_free_space = self.pf.init_gaussian(np.asarray(pose, dtype=np.float64), covariance)
        self._restart()
        self._unconfirmed = None
        return in_free_space

    def global_localization(self) -> None:
        """Forget the pose: particles uniform over the free space (reinitialize_global_localization)."""
        self.pf.init_uniform()
        self._restart()
        self._unconfirmed = 0

    def _restart(self) -> None:
        self.pose_known = True
        self._odom_pose = None

    def request_nomotion_update(self) -> None:
        """Filter on the next scan even if the robot has not moved."""
        self._force_update = True

    # -- each scan -------------------------------------------------------------------------------------
    def prepare_scan(self, ranges: np.ndarray, bearings: np.ndarray, range_min: float,
                     range_max: float) -> LaserScanData:
        """A LaserScanData from a scan's ranges [m] and beam bearings [rad] (see the module docstring)."""
        p = self.parameters
        if p.laser_max_range > 0:
            range_max = min(range_max, p.laser_max_range)
        if p.laser_min_range > 0:
            range_min = max(range_min, p.laser_min_range)
        ranges = np.array(ranges, dtype=np.float64)
        ranges[ranges <= range_min] = range_max
        return LaserScanData(ranges, np.asarray(bearings, dtype=np.float64), float(range_max))

    def update(self, odom_pose: tuple[float, float, float], scan: LaserScanData,
               laser_pose: tuple[float, float, float]) -> UpdateResult:
        """Feed one scan, with the odometry pose (odom -> base, x, y, yaw) at its time and the
        laser's pose in the base frame."""
        if not self.pose_known:
            return UpdateResult(False, False, False, None)
        p = self.parameters
        pose = np.asarray(odom_pose, dtype=np.float64)
        first = self._odom_pose is None
        if first:
            update = True
            self._updates = 0
        else:
            delta = pose - self._odom_pose
            delta[2] = angle_diff(pose[2], self._odom_pose[2])
            update = (abs(delta[0]) > p.update_min_d or abs(delta[1]) > p.update_min_d
                      or abs(delta[2]) > p.update_min_a or self._force_update)
            if update:
                self.pf.motion_update(self.motion_model, pose, delta)
        resampled = False
        if update:
            self._force_update = False
            self._odom_pose = pose
            beams = len(self.laser_model.beams(scan)[0])
            if first or beams:
                # The fit only feeds recovery's averages: without recovery it is not computed.
                judge = not first and self._recovery
                likelihood, explained = self.laser_model.weigh(self.pf.particles, scan, laser_pose,
                                                               within=FIT_DISTANCE if judge else None)
                fit = self._fit(pose, scan, laser_pose, self.pf.weights * likelihood, explained) if judge else math.nan
                self.pf.sensor_update(likelihood, fit=fit)
                self._updates += 1
                if self._updates % p.resample_interval == 0:
                    self.pf.resample()
                    resampled = True
        published = resampled or first
        if published:
            estimate = self.pf.estimate()
            explained = self.laser_model.explained_share(estimate.pose, scan, laser_pose, within=FIT_DISTANCE)
            self._unconfirmed = confirmation(self._unconfirmed, explained)
            judged = explained if self._unconfirmed is None or explained < LOST_SHARE else LOST_SHARE
            self.estimate = estimate._replace(covariance=honest_covariance(estimate.covariance, judged),
                                              explained=explained)
            self._estimate_odom_pose = pose
        return UpdateResult(update, resampled, published, self.estimate)

    def _fit(self, odom_pose: np.ndarray, scan: LaserScanData, laser_pose: tuple[float, float, float],
             weights: np.ndarray, explained: np.ndarray) -> float:
        """What recovery's running averages follow: the share of beams the map explains (within
        FIT_DISTANCE), the larger of two: at the pose reported now (the latest estimate carried
        by odometry) and averaged over the particles by their new `weights` (N,) from their own
        shares `explained` (N,). nan (leave the averages) before any estimate or without beams.

        Nav2 averages the particles' weights. With the product model (`likelihood_field_prob`)
        they move by orders of magnitude with how many beams returned (1e-15 to 1e-24 in one
        drive in turtlebot3_world), so w_fast against w_slow said nothing about being lost. The
        share is in [0, 1] whatever the beams: about 1 while tracking, a half or less once lost.
        The particles' share alone falls with the random particles recovery injects when the
        weights are gentle (`likelihood_field`), which then inject more: it ran away while the
        robot was tracked. The reported pose's alone stays low while the injected particles are
        finding the robot (their cluster is not yet the estimate), so the filter kept replacing
        most of them: 0 of 10 kidnapped robots found, against 10 of 10 with the larger.
        """
        total = float(weights.sum())
        if self.estimate is None or np.isnan(explained).any() or not (total > 0.0 and math.isfinite(total)):
            return math.nan
        reported = compose(self.map_to_odom(), odom_pose)
        at_pose = self.laser_model.explained_share(reported, scan, laser_pose, within=FIT_DISTANCE)
        return max(at_pose, float(weights @ explained) / total)

    def map_to_odom(self) -> np.ndarray | None:
        """The map -> odom transform (x, y, yaw) that puts the robot at the latest estimate, or
        None before the first one."""
        if self.estimate is None:
            return None
        return compose(self.estimate.pose, inverse(self._estimate_odom_pose))
