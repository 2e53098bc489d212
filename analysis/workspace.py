"""The workspace of a serial arm: volume (area of a planar arm), reach, bounding box, manipulability.

The joint space is sampled uniformly within the joint limits (a revolute joint without limits over one
full turn, −π … π), the tool point is computed for every sample in chunks by the arm's batched forward
kinematics (:func:`tool_positions`), and the workspace **volume** is the number of voxels of edge ``h``
the tool points occupy, times h³ (h² and an area for a planar arm, whose tool points are found to lie in
one plane; h and a length for a line).

A voxel estimate has two errors: too few samples leave cells inside the workspace empty (the estimate
grows with N), and a cell that the boundary cuts counts whole (the estimate shrinks with h, to first
order in h). The reported volume is therefore the Richardson extrapolation to h → 0 from the counts at
h and 2h, V = 2·V(h) − V(2h), which removes the error of first order in h once the cells are filled;
the default resolution keeps about :data:`SAMPLES_PER_CELL` samples per occupied cell (estimated from
the first batch of samples) so that they are. :func:`workspace` records V at N/64 … N samples and V(h)
at h … 8h, so the convergence is seen; at a number of samples too few to fill the cells 2·V(h) − V(2h) can fall
below zero, and is recorded as ``None`` (not yet measured) rather than a negative measure.

Manipulability (Yoshikawa's w = √det(J Jᵀ) and the smallest singular value σ_min) and the singular
configurations are computed on a subsample by :mod:`armlab.analysis.singular`.

With ``collisions`` the **collision-free volume** is measured beside the raw one, the same way, from the samples
in which no checked pair touches (:class:`armlab.collision.model.CollisionModel`: the arm against itself and a
scene's obstacles): the tool points a pose that does not pass through the arm or an obstacle reaches.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import above, below, tolerated
from armlab.kinematics.differential import jacobian
from armlab.limits import LIMITS, check_range, whole_text

if TYPE_CHECKING:
    from armlab.collision.scene import Scene
    from armlab.models.arm import Arm

__all__ = [
    "DEFAULT_SAMPLES",
    "MAX_SAMPLES",
    "MAX_SEED",
    "SAMPLES_PER_CELL",
    "Workspace",
    "check_resolution",
    "check_samples",
    "check_seed",
    "default_resolution",
    "joint_box",
    "motion_rank",
    "reach_bound",
    "sample_joints",
    "tool_positions",
    "workspace",
    "workspace_plane",
]

#: Joint-space samples of ``armlab workspace`` unless ``--samples`` says otherwise.
DEFAULT_SAMPLES = 1_000_000
#: Most joint-space samples of one workspace (about 20 minutes of forward kinematics on one core).
MAX_SAMPLES = 1_000_000_000
#: Largest seed of the random samples.
MAX_SEED = 2**32 - 1
#: Samples per cell of the reach's ball that the default resolution aims for.
SAMPLES_PER_CELL = 40
#: Configurations per batch of forward kinematics (bounds the memory of a workspace run).
CHUNK = 1 << 16
#: Most cells of an occupancy grid (one byte each).
MAX_CELLS = 200_000_000
#: Points kept for the plots and the 3-D point cloud, and configurations whose Jacobian is evaluated.
KEPT = 40_000
#: The resolutions of the convergence study, in multiples of h, and the sample fractions, 2^-k.
RESOLUTION_FACTORS = (1, 2, 4, 8)
SAMPLE_HALVINGS = 6


def joint_box(arm: Arm) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The sampled joint ranges (rad or m): the limits, a revolute joint without limits over −π … π.

    ``ValueError`` for a prismatic joint without limits (its stroke would be unbounded).
    """
    lower, upper = arm.limit_arrays()
    for i, (name, revolute) in enumerate(zip(arm.joint_names, arm.revolute, strict=True)):
        if np.isinf(lower[i]) or np.isinf(upper[i]):
            if not revolute:
                raise ValueError(f"{arm.name}: prismatic joint {name} has no limits; its workspace is unbounded")
            lower[i], upper[i] = -np.pi, np.pi
    return lower, upper


def sample_joints(arm: Arm, samples: int, rng: np.random.Generator | int | None = 0) -> NDArray[np.float64]:
    """``samples`` configurations drawn uniformly from :func:`joint_box`, shape ``(samples, n)``."""
    lower, upper = joint_box(arm)
    rng = np.random.default_rng(rng)
    return lower + (upper - lower) * rng.random((int(samples), arm.n))


def tool_positions(arm: Arm, q: ArrayLike) -> NDArray[np.float64]:
    """The tool point of every configuration of the batch ``q`` (..., n), shape ``(..., 3)``, in metres:
    the origin of :meth:`Arm.forward`'s tool frame (the paper's own batched forward kinematics)."""
    return arm.forward(q).tool[..., :3, 3]


def motion_rank(arm: Arm, q: NDArray[np.float64], basis: NDArray[np.float64]) -> int:
    """Independent directions (within ``basis``, (d, 3)) the tool point moves in: the largest rank of the
    translational Jacobian over the configurations ``q`` (k, n) (:func:`armlab.kinematics.differential.jacobian`)."""
    J = basis @ jacobian(arm, q)[:, :3, :]  # (k, d, n)
    s = np.linalg.svd(J, compute_uv=False)
    return int(np.max(np.sum(above(s / max(float(s.max()), 1e-300), 0.0), axis=-1)))  # beyond round-off of the largest


def reach_bound(arm: Arm) -> float:
    """An upper bound of the tool point's distance from the base (m): the sum of every link's offset,
    the tool's, and each prismatic joint's largest stroke."""
    lower, upper = joint_box(arm)
    offsets = sum(float(np.linalg.norm(row.P)) for row in arm.table.rows)
    strokes = sum(max(abs(lo), abs(hi)) for lo, hi, r in zip(lower, upper, arm.revolute, strict=True) if not r)
    return offsets + float(np.linalg.norm(np.asarray(arm.table.tool)[:3, 3])) + strokes


def workspace_plane(points: ArrayLike, tol: float = 1e-9) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The affine subspace the points ``(M, 3)`` span: (origin (3,), orthonormal basis (d, 3)), d = 1, 2 or 3.

    A direction counts when the points spread along it by more than ``tol`` times their largest spread.
    A subspace whose normal is a coordinate axis keeps the other coordinate axes as its basis (rr: x, y).
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    origin = pts.mean(axis=0)
    _, s, vt = np.linalg.svd(pts - origin, full_matrices=False)
    d = int(np.sum(~tolerated(s / max(s[0], 1e-300), tol)))
    if d == 0:
        raise ValueError("the tool point does not move: the workspace is a single point")
    basis = vt[:d]
    axes = np.flatnonzero(~tolerated(np.abs(basis).max(axis=0), tol))
    if len(axes) == d:  # the subspace is spanned by coordinate axes: use them
        basis = np.eye(3)[axes]
        origin = np.where(np.isin(np.arange(3), axes), 0.0, origin)
    return origin, basis


def _check_measurable(arm: Arm, bound: float, motions: int) -> None:
    """``ValueError`` unless voxels of an allowed edge can measure a workspace within ``bound`` (m) whose tool point
    moves in ``motions`` directions: it moves at all, and reaches between the smallest voxel edge and the largest
    coordinate armlab accepts (:data:`armlab.limits.LIMITS`)."""
    if motions == 0:
        raise ValueError(f"{arm.name}: the tool point does not move (every joint's range is empty or moves it "
                         "nowhere): there is no workspace to measure")
    far, fine = LIMITS["coordinate"], LIMITS["resolution"]
    if above(bound, far.high):
        raise ValueError(f"{arm.name}: the tool point reaches up to {bound:.3g} m, beyond {far.high:g} m ({far.why}): "
                         "its workspace cannot be measured")
    if below(bound, fine.low):
        raise ValueError(f"{arm.name}: the tool point reaches only {bound:.3g} m, less than the smallest voxel edge "
                         f"{fine.low:g} m: its workspace cannot be measured")


def default_resolution(coords: ArrayLike, samples: int, bound: float) -> float:
    """Voxel edge h (m) for ``samples`` samples: about :data:`SAMPLES_PER_CELL` samples per occupied cell, and no
    finer than a grid of :data:`MAX_CELLS` cells over ±``bound`` allows.

    The occupied measure is estimated from a pilot set of points ``coords`` (M, d) (in the workspace's
    own coordinates, within ±``bound``): the cells of a coarse grid holding about 10 pilot points per
    cell of the reach's ball (disc) that they occupy.
    """
    coords = np.asarray(coords, dtype=float)
    m, dim = coords.shape
    ball = {1: 2 * bound, 2: math.pi * bound**2, 3: 4 / 3 * math.pi * bound**3}[dim]
    pilot = (10 * ball / m) ** (1.0 / dim)
    index = np.floor((coords + bound) / pilot).astype(np.int64)
    flat = np.ravel_multi_index(tuple(index.T), (math.ceil(2 * bound / pilot) + 1,) * dim)
    h = (SAMPLES_PER_CELL * np.unique(flat).size * pilot**dim / samples) ** (1.0 / dim)
    # no finer than MAX_CELLS cells over ±bound allow (urm6 at 1e9 samples would ask for more): _Occupancy makes
    # ceil(2 bound / h) + 1 cells a side, at most `side` + 1 for this h (one more for ceil's round-off)
    side = math.floor(MAX_CELLS ** (1.0 / dim)) - 2
    return max(h, 2 * bound / side)


@dataclass
class Workspace:
    """What :func:`workspace` found. Lengths in m, volume in m^dim (``volume_unit``): ``volume`` extrapolated
    to h → 0, ``volume_voxels`` the occupied cells' at ``resolution``.

    ``points``: up to :data:`KEPT` tool points (M, 3) of the configurations ``q`` (M, n), with their
    ``manipulability`` and ``sigma_min`` (M,) where computed. ``convergence`` holds the estimates at
    fewer samples and coarser resolutions.
    """

    arm: str
    samples: int
    dim: int
    origin: NDArray[np.float64]
    basis: NDArray[np.float64]
    resolution: float
    volume: float
    volume_voxels: float
    reach: float
    bbox: NDArray[np.float64]  # (2, 3): min and max of x, y, z
    convergence: dict[str, Sequence[float | None]]
    q: NDArray[np.float64]
    points: NDArray[np.float64]
    seed: int
    wall_time: float
    manipulability: NDArray[np.float64] | None = None
    sigma_min: NDArray[np.float64] | None = None
    singular: dict[str, Any] = field(default_factory=dict)
    motions: int = 3  # independent directions the tool point moves in (rank of J_v): < dim, a curved surface
    #: With ``collisions``: the volume from the collision-free samples only, their share, what was checked and, per
    #: kept point, whether its configuration is collision-free.
    collision_free_volume: float | None = None
    collision_free_fraction: float | None = None
    min_clearance: float | None = None  # m, over every sample and pair; < 0: the deepest penetration
    collision_check: str = ""
    free: NDArray[np.bool_] | None = None

    @property
    def note(self) -> str:
        """Why the volume is 0 when the tool point moves in fewer directions than its positions span."""
        if self.motions >= self.dim:
            return ""
        shape = {1: "a curve", 2: "a curved surface"}[self.motions]
        return (f"the tool point moves in {self.motions} direction(s) only: its positions form {shape} in "
                f"{self.dim}-D, whose {self.measure} is 0 (the occupied voxels are a shell of thickness h)")

    @property
    def volume_unit(self) -> str:
        """m, m² or m³."""
        return {1: "m", 2: "m²", 3: "m³"}[self.dim]

    @property
    def measure(self) -> str:
        """"length", "area" or "volume"."""
        return {1: "length", 2: "area", 3: "volume"}[self.dim]

    def summary(self) -> dict[str, Any]:
        """The numbers of ``workspace.json``."""
        out: dict[str, Any] = {
            "arm": self.arm,
            "samples": self.samples,
            "seed": self.seed,
            "measure": self.measure,
            "volume": self.volume,
            "volume_unit": self.volume_unit,
            "volume_voxels": self.volume_voxels,
            **({"note": self.note} if self.note else {}),
            "resolution": self.resolution,
            "reach": self.reach,
            "bbox": {"min": self.bbox[0].tolist(), "max": self.bbox[1].tolist()},
            "plane": {"origin": self.origin.tolist(), "basis": self.basis.tolist()},
            "convergence": self.convergence,
            "wall_time_s": self.wall_time,
        }
        if self.manipulability is not None and self.sigma_min is not None:
            out["manipulability"] = _stats(self.manipulability) | {"configurations": int(self.manipulability.size)}
            out["sigma_min"] = _stats(self.sigma_min)
        if self.singular:  # keys starting with "_" hold what the plots need
            out["singular"] = {k: v for k, v in self.singular.items() if not k.startswith("_")}
        if self.collision_check:
            out["collision_free_volume"] = self.collision_free_volume
            out["collision_free_fraction"] = self.collision_free_fraction
            out["min_clearance"] = self.min_clearance
            out["collision_check"] = self.collision_check
        return out


def _stats(values: NDArray[np.float64]) -> dict[str, float]:
    return {"min": float(values.min()), "median": float(np.median(values)), "mean": float(values.mean()),
            "max": float(values.max())}


class _Occupancy:
    """Boolean grids of cells of edge h·f (f in :data:`RESOLUTION_FACTORS`) over the cube ±bound."""

    def __init__(self, h: float, bound: float, dim: int) -> None:
        self.h, self.bound, self.dim = h, bound, dim
        self.cells = math.ceil(2 * bound / h) + 1
        if self.cells**dim > MAX_CELLS:
            raise ValueError(f"resolution {h:g} m is too fine for a reach of {bound:g} m: {self.cells}^{dim} cells "
                             f"exceed {MAX_CELLS:.0e}; give a coarser --resolution")
        self.grids = [np.zeros((-(-self.cells // f)) ** dim, dtype=bool) for f in RESOLUTION_FACTORS]

    def add(self, coords: NDArray[np.float64]) -> None:
        index = np.floor((coords + self.bound) / self.h).astype(np.int64)
        for f, grid in zip(RESOLUTION_FACTORS, self.grids, strict=True):
            n = -(-self.cells // f)
            cell = index // f
            flat = cell[:, 0]
            for j in range(1, self.dim):
                flat = flat * n + cell[:, j]
            grid[flat] = True

    @staticmethod
    def extrapolated(measures: list[float]) -> float:
        """Richardson's 2·V(h) − V(2h): the voxel estimate extrapolated to h → 0."""
        return 2 * measures[0] - measures[1]

    def measures(self) -> list[float]:
        """The occupied measure at every resolution, finest first."""
        return [float(np.count_nonzero(g)) * (self.h * f) ** self.dim for f, g in zip(RESOLUTION_FACTORS, self.grids,
                                                                                      strict=True)]


def workspace(
    arm: Arm,
    samples: int = DEFAULT_SAMPLES,
    resolution: float | None = None,
    seed: int = 0,
    jacobians: bool = True,
    collisions: bool = False,
    scene: Scene | None = None,
) -> Workspace:
    """Sample ``arm``'s joint space and measure its workspace (see the module docstring).

    ``samples``: configurations (≥ 1000); ``resolution``: voxel edge h in m (default
    :func:`default_resolution`); ``seed``: the random generator's seed (the same seed, the same
    samples); ``jacobians``: also evaluate manipulability and singular configurations on a subsample;
    ``collisions`` (implied by a ``scene``): also the collision-free volume, checking the arm against itself and
    ``scene``'s obstacles (``ValueError`` for an arm without collision geometry).
    """
    began = time.perf_counter()
    samples = check_samples(samples)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    first = sample_joints(arm, min(samples, CHUNK), rng)
    first_points = tool_positions(arm, first)
    origin, basis = workspace_plane(first_points)
    dim = basis.shape[0]
    motions = motion_rank(arm, first[:16], basis)
    bound = reach_bound(arm) + float(np.linalg.norm(origin))
    _check_measurable(arm, bound, motions)
    h = check_resolution(resolution) if resolution is not None else \
        default_resolution((first_points - origin) @ basis.T, samples, bound)
    grid = _Occupancy(h, bound, dim)
    model, free_grid, free_count, kept_free, nearest = None, _Occupancy(h, bound, dim), 0, [], np.inf
    if collisions or scene is not None:
        # lazy: armlab.collision imports Drake
        from armlab.collision.model import CollisionModel

        model = CollisionModel(arm, scene)
    checkpoints = sorted({samples >> k for k in range(SAMPLE_HALVINGS + 1) if samples >> k >= 1})
    counts: list[float | None] = []
    kept_q: list[NDArray] = []
    kept_points: list[NDArray] = []
    reach, lo, hi = 0.0, np.full(3, np.inf), np.full(3, -np.inf)
    done = 0
    pending = [(first, first_points)]
    while done < samples:
        if not pending:
            q = sample_joints(arm, min(CHUNK, samples - done), rng)
            pending.append((q, tool_positions(arm, q)))
        q, points = pending.pop()
        take = next(c for c in checkpoints if c > done) - done  # stop at each checkpoint to record it
        if len(q) > take:
            pending.append((q[take:], points[take:]))
            q, points = q[:take], points[:take]
        coords = (points - origin) @ basis.T
        grid.add(coords)
        if model is not None:
            clearance = model.distances(q).distance
            free = np.all(~below(clearance, 0.0), axis=-1)  # in contact only below zero (armlab.bounds)
            nearest = min(nearest, float(clearance.min(initial=np.inf)))
            free_grid.add(coords[free])
            free_count += int(np.count_nonzero(free))
        reach = max(reach, float(np.sqrt(np.max(np.einsum("ij,ij->i", points, points)))))
        lo, hi = np.minimum(lo, points.min(axis=0)), np.maximum(hi, points.max(axis=0))
        done += len(points)
        if done in checkpoints:  # below zero: the cells are not filled yet, and no measure is negative
            estimate = grid.extrapolated(grid.measures())
            counts.append(None if below(estimate, 0.0) else estimate)
        kept = sum(len(k) for k in kept_q)
        if kept < KEPT:
            kept_q.append(q[: KEPT - kept])
            kept_points.append(points[: KEPT - kept])
            if model is not None:
                kept_free.append(free[: KEPT - kept])
    measures = grid.measures()
    result = Workspace(
        arm=arm.name, samples=samples, dim=dim, origin=origin, basis=basis, resolution=h,
        volume=grid.extrapolated(measures) if motions == dim else 0.0, volume_voxels=measures[0], motions=motions,
        reach=reach, bbox=np.stack([lo, hi]),
        convergence={"samples": [float(c) for c in checkpoints], "volume_vs_samples": counts,
                     "resolution": [h * f for f in RESOLUTION_FACTORS], "volume_vs_resolution": measures},
        q=np.concatenate(kept_q), points=np.concatenate(kept_points), seed=seed, wall_time=0.0,
    )
    if model is not None:
        free_measures = free_grid.measures()
        result.collision_free_volume = free_grid.extrapolated(free_measures) if motions == dim else 0.0
        result.collision_free_fraction = free_count / samples
        result.min_clearance = nearest if np.isfinite(nearest) else None
        where = "itself" if scene is None else f"itself and the {len(scene.obstacles)} obstacle(s) of {scene.source}"
        result.collision_check = f"{len(model.pairs)} pair(s) checked: the arm against {where}"
        result.free = np.concatenate(kept_free)
    if jacobians:
        # lazy: cycle, armlab.analysis.singular imports this module (joint_box, tool_positions)
        from armlab.analysis.singular import add_manipulability

        add_manipulability(arm, result)
    result.wall_time = time.perf_counter() - began
    return result


def _whole(value: Any, name: str, low: int, high: int, why: str) -> int:
    """``value`` as an int if it is a whole number in ``low … high``; else a one-line ``ValueError`` naming ``name``."""
    whole = (isinstance(value, (int, np.integer)) and not isinstance(value, bool)) or \
        (isinstance(value, float) and value.is_integer())
    if not whole or not low <= value <= high:  # not a bound: a user's count checked against its accepted range
        shown = whole_text(value) if whole and abs(value) <= 1e308 else repr(value)[:40]
        raise ValueError(f"{name} {shown} is not allowed: give a whole number {low} … {whole_text(high)} ({why})")
    return int(value)


def check_samples(samples: Any, name: str = "samples") -> int:
    """The joint-space sample count as an int, 1000 … :data:`MAX_SAMPLES`; ``ValueError`` naming ``name`` else."""
    return _whole(samples, name, 1000, MAX_SAMPLES, "more would take hours")


def check_seed(seed: Any, name: str = "seed") -> int:
    """The random samples' seed as an int, 0 … :data:`MAX_SEED`; ``ValueError`` naming ``name`` else."""
    return _whole(seed, name, 0, MAX_SEED, "the seed of the random samples")


def check_resolution(h: Any, name: str = "resolution") -> float:
    """The voxel edge (m) as a float within :data:`armlab.limits.LIMITS`' range; ``ValueError`` naming ``name``."""
    try:
        value = float(h)
    except (TypeError, ValueError):
        raise ValueError(f"{name} {h!r} is not allowed: give a voxel edge in metres") from None
    return float(check_range(value, name, key="resolution"))
