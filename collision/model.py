"""An arm and its scene in Drake's ``SceneGraph``: which pairs are checked, and their signed distances.

:class:`CollisionModel` builds the arm's plant with its collision geometry and the scene's obstacles through
the one plant builder (:func:`armlab.models.plant.add_arm_plant`, ``PlantOptions(scene=…)``) and takes the
pairs to check from ``SceneGraph``: every pair of geometries that is not filtered, i.e. not on adjacent links
(Drake filters those), not both on the stand or the world, and not filtered by the arm's file. A pair is named
by its two owners (a link's name, or an obstacle's), the arm's link first; geometries of the same two owners
(the stand's disc and column) count as one pair, the nearest.

Two ways to the same numbers: :meth:`CollisionModel.drake` asks ``SceneGraph`` sample by sample
(``ComputeSignedDistancePairClosestPoints``; a capsule or sphere against the floor, which Drake's pairwise
query does not support, from Drake's signed distance of its axis' ends to the floor, less the radius), and
:meth:`CollisionModel.numpy` computes a link's capsule or sphere against capsules, spheres, floors and boxes in
batches (:mod:`armlab.collision.capsules`) from the arm's forward kinematics. :meth:`CollisionModel.distances`
takes numpy where every pair is of those, Drake otherwise (cylinders, meshes, boxes on links). Drake's capsule
and box distances are GJK's, whose precision is fixed inside Drake (drake#14731): above the exact ones by up to
about 2e-4 m, never below; its sphere and floor distances are closed forms, as numpy's all are.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.collision.capsules import capsule_box, capsule_capsule, capsule_floor
from armlab.kinematics.batch import as_batch, blocks
from armlab.models.plant import PlantOptions, add_arm_plant, default_context

if TYPE_CHECKING:
    from armlab.collision.scene import Scene
    from armlab.models.arm import Arm

__all__ = ["Clearances", "CollisionModel", "NoGeometryError", "Part", "geometry_owner"]


class NoGeometryError(ValueError):
    """The arm has no collision geometry: nothing of it can be checked."""

    @classmethod
    def of(cls, arm: Arm) -> NoGeometryError:
        """The error for ``arm``, saying how to give it collision geometry."""
        return cls(f"{arm.name} has no collision geometry, so nothing can be checked: give its DH table a radius "
                   "column (a capsule per link) or its URDF or SDFormat <collision> elements (MJCF: <geom>s)")


@dataclass(frozen=True)
class Part:
    """One collision geometry as the numpy path sees it: on ``owner`` (a link or obstacle name), fixed in the
    arm's frame ``frame`` (an index of ``arm.table.frames(q)``: 0 the base = world, i link i, n+1 the tool).

    ``kind``: ``"capsule"`` (axis ``a``–``b`` (m) in that frame, radius m; a sphere has ``a`` = ``b``),
    ``"floor"`` (through ``a`` with outward normal ``b``), ``"box"`` (half edges ``a`` (m), its pose in that
    frame ``X``) or ``"other"`` (a cylinder, mesh …: Drake only). ``extent``: how far from the frame's origin the
    shape reaches (m), what :meth:`CollisionModel.motion_bound` needs.
    """

    owner: str
    frame: int
    kind: str
    a: NDArray[np.float64]
    b: NDArray[np.float64]
    radius: float = 0.0
    X: NDArray[np.float64] | None = None
    #: The farthest any point of the shape lies from its frame's origin (m; inf for a floor).
    extent: float = np.inf


@dataclass(frozen=True)
class Clearances:
    """Signed distances of ``pairs`` (each ``(owner A, owner B)``) over a batch of N configurations.

    ``distance`` (m, ``(N, P)``): negative when the two overlap (−distance is the penetration depth);
    ``point_a``, ``point_b`` (m, ``(N, P, 3)``, world): the closest points on A and on B.
    """

    pairs: tuple[tuple[str, str], ...]
    distance: NDArray[np.float64]
    point_a: NDArray[np.float64]
    point_b: NDArray[np.float64]

    def names(self) -> list[str]:
        """Each pair as ``"A–B"``."""
        return [f"{a}–{b}" for a, b in self.pairs]


def geometry_owner(plant: Any, inspector: Any, geometry: Any) -> str:
    """The owner a pair names for ``geometry`` of ``plant``'s ``SceneGraph`` (``inspector``): its link's name, or an
    obstacle's name in the scene (geometry of the world body)."""
    body = plant.GetBodyFromFrameId(inspector.GetFrameId(geometry))
    if body.index() == plant.world_body().index():
        return str(inspector.GetName(geometry))
    return str(body.name())


def _transform(X: Any) -> NDArray[np.float64]:
    return np.asarray(X.GetAsMatrix4())


class CollisionModel:
    """The arm's collision geometry and the scene's in one ``SceneGraph`` (see the module docstring).

    :class:`NoGeometryError` (a ``ValueError``) when the arm has no collision geometry: a check would report
    "no collision" for an arm it cannot see.
    """

    def __init__(self, arm: Arm, scene: Scene | None = None) -> None:
        # lazy: Drake is imported by the commands that need it (armlab._lazy)
        from pydrake.systems.framework import DiagramBuilder

        self.arm, self.scene = arm, scene
        builder = DiagramBuilder()
        plant, scene_graph = add_arm_plant(builder, arm, PlantOptions(geometry=True, scene=scene))
        assert scene_graph is not None, "PlantOptions(geometry=True) gives a scene graph"
        self.plant, self.scene_graph = plant, scene_graph
        self.diagram = builder.Build()
        self.context = default_context(self.diagram)
        self._plant_context = plant.GetMyMutableContextFromRoot(self.context)
        self._scene_context = scene_graph.GetMyContextFromRoot(self.context)
        inspector = scene_graph.model_inspector()
        self._inspector = inspector
        ids = [g for g in inspector.GetAllGeometryIds() if inspector.GetProximityProperties(g) is not None]
        frames = self._frame_of_body()
        self._parts = {g: self._part(g, frames) for g in ids}
        if not any(part.frame > 0 for part in self._parts.values()):
            raise NoGeometryError.of(arm)
        owners = {g: part.owner for g, part in self._parts.items()}
        pairs: dict[tuple[str, str], list[tuple[Any, Any]]] = {}
        for a, b in sorted(inspector.GetCollisionCandidates(), key=lambda p: (owners[p[0]], owners[p[1]])):
            if self._parts[a].frame < self._parts[b].frame:
                a, b = b, a  # the link further out first: the arm's before the stand's and the obstacles'
            pairs.setdefault((owners[a], owners[b]), []).append((a, b))
        self.pairs = tuple(pairs)
        self._geometry_pairs = [pair for group in pairs.values() for pair in group]
        self._group = np.repeat(np.arange(len(pairs)), [len(group) for group in pairs.values()])

    @classmethod
    def optional(cls, arm: Arm, scene: Scene | None = None) -> CollisionModel | None:
        """The model of ``arm`` in ``scene``, or None when the arm has no collision geometry and there is no
        scene (nothing to check: the caller says so, never "no collision"); with a scene, :class:`NoGeometryError`."""
        try:
            return cls(arm, scene)
        except NoGeometryError:
            if scene is not None:
                raise
            return None

    # ------------------------------------------------------------------ set-up
    def _frame_of_body(self) -> dict[Any, tuple[int, NDArray[np.float64]]]:
        """Body index → (the arm's frame index it is fixed in, its pose in that frame) for every body."""
        plant, context = self.plant, self._plant_context
        plant.SetPositions(context, np.zeros(self.arm.n))
        anchors = [plant.world_body()] + [plant.GetJointByName(name).child_body() for name in self.arm.joint_names]
        out = {}
        for frame, anchor in enumerate(anchors):
            X_WA = _transform(plant.EvalBodyPoseInWorld(context, anchor))
            for body in plant.GetBodiesWeldedTo(anchor):
                X_WB = _transform(plant.EvalBodyPoseInWorld(context, body))
                out[body.index()] = (frame, np.linalg.solve(X_WA, X_WB))
        return out

    def _part(self, geometry: Any, frames: dict[Any, tuple[int, NDArray[np.float64]]]) -> Part:
        """The geometry as numpy sees it (:class:`Part`), in the arm's frame its body is fixed in."""
        from pydrake.geometry import Box, Capsule, Convex, Cylinder, HalfSpace, Mesh, Sphere

        inspector = self._inspector
        body = self.plant.GetBodyFromFrameId(inspector.GetFrameId(geometry))
        frame, X_FB = frames[body.index()]
        X_FG = X_FB @ _transform(inspector.GetPoseInFrame(geometry))
        shape, owner = inspector.GetShape(geometry), geometry_owner(self.plant, inspector, geometry)
        centre = float(np.linalg.norm(X_FG[:3, 3]))
        if isinstance(shape, Capsule):
            half = X_FG[:3, 2] * shape.length() / 2
            return Part(owner, frame, "capsule", X_FG[:3, 3] - half, X_FG[:3, 3] + half, shape.radius(),
                        extent=centre + shape.length() / 2 + shape.radius())
        if isinstance(shape, Sphere):
            return Part(owner, frame, "capsule", X_FG[:3, 3], X_FG[:3, 3].copy(), shape.radius(),
                        extent=centre + shape.radius())
        if isinstance(shape, HalfSpace):
            return Part(owner, frame, "floor", X_FG[:3, 3], X_FG[:3, 2])
        if isinstance(shape, Box):
            half_edges = np.array([shape.width(), shape.depth(), shape.height()]) / 2
            return Part(owner, frame, "box", half_edges, np.zeros(3), X=X_FG,
                        extent=centre + float(np.linalg.norm(half_edges)))
        if isinstance(shape, Cylinder):
            reach = centre + float(np.hypot(shape.length() / 2, shape.radius()))
        elif isinstance(shape, Convex | Mesh):
            hull = inspector.GetConvexHull(geometry)
            vertices = np.array([hull.vertex(i) for i in range(hull.num_vertices())])
            reach = float(np.linalg.norm(vertices @ X_FG[:3, :3].T + X_FG[:3, 3], axis=1).max())
        else:
            reach = np.inf
        return Part(owner, frame, "other", X_FG[:3, 3], X_FG[:3, 2], extent=reach)

    def motion_bound(self) -> NDArray[np.float64]:
        """Per joint j, ``(n,)``: how far (m) a point of the arm's geometry can move per unit of q_j (rad or m): no
        point moves more than Σ_j bound_j·|Δq_j| between two configurations Δq apart (along the straight joint
        path between them), so no clearance changes by more than twice that (both shapes of a pair may move).

        A revolute joint's bound is the farthest the geometry beyond it reaches from its axis, bounded along the
        chain: the joint origins' distances (each constant on its link), the prismatic strokes between and each
        shape's :attr:`Part.extent`; a prismatic joint's is 1. ``inf`` where a shape's reach is unknown."""
        n, table = self.arm.n, self.arm.table
        span = [float(np.linalg.norm(row.P)) for row in table.rows[1:]]  # frame k+1's origin in frame k, k = 1 … n−1
        lower, upper = self.arm.limit_arrays(unlimited=0.0)
        stroke = np.where(self.arm.revolute, 0.0, np.maximum(np.abs(lower), np.abs(upper)))
        reach = np.zeros(n + 1)  # the farthest shape of each frame 1 … n from its origin
        for part in self._parts.values():
            if part.frame > 0:
                reach[part.frame] = max(reach[part.frame], part.extent)
        bound = np.ones(n)
        for j in range(1, n + 1):
            if self.arm.revolute[j - 1]:
                reaching = [f for f in range(j, n + 1) if reach[f] > 0]  # not a bound: links with a reach at all
                bound[j - 1] = max((sum(span[j - 1:f - 1]) + float(stroke[j:f].sum()) + reach[f] for f in reaching),
                                   default=0.0)
        return bound

    @property
    def numpy_ready(self) -> bool:
        """True when every pair is a capsule (or sphere) against a capsule, sphere, floor or box: :meth:`numpy`
        computes them all (a box that the capsule's axis enters: Drake, at those samples)."""
        return all(self._parts[a].kind == "capsule" and self._parts[b].kind in ("capsule", "floor", "box")
                   for a, b in self._geometry_pairs)

    # ---------------------------------------------------------------- queries
    def distances(self, q: ArrayLike, depth: bool = True) -> Clearances:
        """The clearances of every pair at ``q`` ``(n,)`` or ``(N, n)`` (rad, m): numpy when it can, else Drake;
        ``depth``: as :meth:`numpy`'s."""
        return self.numpy(q, depth) if self.numpy_ready else self.drake(q)

    def _reduce(self, q: NDArray[np.float64], distance: NDArray, point_a: NDArray, point_b: NDArray) -> Clearances:
        """Per-geometry-pair results ``(N, G)`` → per owner pair ``(N, P)``: the nearest geometry pair of each."""
        count = len(self.pairs)
        if len(self._geometry_pairs) != count:
            order = np.argsort(self._group, kind="stable")
            starts = np.searchsorted(self._group[order], np.arange(count))
            best = np.empty((distance.shape[0], count), dtype=np.intp)
            for k, start in enumerate(starts):
                stop = starts[k + 1] if k + 1 < count else len(order)
                columns = order[start:stop]
                best[:, k] = columns[np.argmin(distance[:, columns], axis=1)]
            rows = np.arange(distance.shape[0])[:, None]
            distance, point_a, point_b = distance[rows, best], point_a[rows, best], point_b[rows, best]
        shape = q.shape[:-1]
        return Clearances(self.pairs, distance.reshape(shape + (count,)), point_a.reshape(shape + (count, 3)),
                          point_b.reshape(shape + (count, 3)))

    def drake(self, q: ArrayLike) -> Clearances:
        """The clearances of every pair at ``q`` ``(n,)`` or ``(N, n)``, asked of ``SceneGraph`` sample by sample."""
        q = as_batch(q, self.arm.n)
        flat = q.reshape(-1, self.arm.n)
        G = len(self._geometry_pairs)
        distance, point_a, point_b = np.empty((len(flat), G)), np.empty((len(flat), G, 3)), np.empty((len(flat), G, 3))
        port = self.scene_graph.get_query_output_port()
        for k, qk in enumerate(flat):
            self.plant.SetPositions(self._plant_context, qk)
            query = port.Eval(self._scene_context)
            for j, (a, b) in enumerate(self._geometry_pairs):
                distance[k, j], point_a[k, j], point_b[k, j] = self._drake_pair(query, a, b)
        return self._reduce(q, distance, point_a, point_b)

    def _drake_pair(self, query: Any, a: Any, b: Any) -> tuple[float, NDArray, NDArray]:
        """Drake's signed distance of geometries ``a`` and ``b`` and the closest points (world)."""
        if self._parts[b].kind != "floor":
            result = query.ComputeSignedDistancePairClosestPoints(a, b)
            X_A, X_B = query.GetPoseInWorld(a), query.GetPoseInWorld(b)
            return float(result.distance), X_A.multiply(result.p_ACa), X_B.multiply(result.p_BCb)
        # the floor: Drake's signed distance to it of the lowest points the shape can have, less its radius
        X_WG = _transform(query.GetPoseInWorld(a))
        points, radius = self._lowest_candidates(a, X_WG, _transform(query.GetPoseInWorld(b))[:3, 2])
        best: tuple[float, NDArray, NDArray] | None = None
        for p in points:
            (hit,) = [d for d in query.ComputeSignedDistanceToPoint(p) if d.id_G == b]
            height = float(hit.distance)
            if best is None or height - radius < best[0]:
                normal = np.asarray(hit.grad_W)
                best = (height - radius, p - radius * normal, p - height * normal)
        assert best is not None
        return best

    def _lowest_candidates(self, geometry: Any, X_WG: NDArray[np.float64], up: NDArray[np.float64]
                           ) -> tuple[list[NDArray[np.float64]], float]:
        """Points (world, m) among which lies the lowest of ``geometry`` along ``up``, and the radius to take off:
        a capsule's axis ends (its radius), a sphere's centre, a box's corners, a mesh's convex hull's vertices, a
        cylinder's lowest rim point. ``ValueError`` for another shape."""
        from pydrake.geometry import Box, Capsule, Convex, Cylinder, Mesh, Sphere

        shape = self._inspector.GetShape(geometry)
        R, c = X_WG[:3, :3], X_WG[:3, 3]
        if isinstance(shape, Capsule | Sphere):
            half = shape.length() / 2 if isinstance(shape, Capsule) else 0.0
            return [c - half * R[:, 2], c + half * R[:, 2]], shape.radius()
        if isinstance(shape, Box):
            corners = np.array(np.meshgrid(*([-0.5, 0.5],) * 3)).reshape(3, -1).T * [shape.width(), shape.depth(),
                                                                                     shape.height()]
            return list(corners @ R.T + c), 0.0
        if isinstance(shape, Mesh | Convex):
            hull = self._inspector.GetConvexHull(geometry)
            return [R @ np.asarray(hull.vertex(i)) + c for i in range(hull.num_vertices())], 0.0
        if isinstance(shape, Cylinder):
            axis = R[:, 2] * np.sign(R[:, 2] @ up or 1.0)
            side = up - (up @ R[:, 2]) * R[:, 2]
            rim = side / np.linalg.norm(side) if np.linalg.norm(side) > 1e-12 else np.zeros(3)
            return [c - shape.length() / 2 * axis - shape.radius() * rim], 0.0
        raise ValueError(f"{self._parts[geometry].owner}: a {type(shape).__name__} cannot be checked against the "
                         "floor: give the link a box, sphere, cylinder, capsule or mesh")

    def numpy(self, q: ArrayLike, depth: bool = True) -> Clearances:
        """The clearances of every pair at ``q`` ``(n,)`` or ``(N, n)``, computed in batches with numpy
        (:mod:`armlab.collision.capsules`); ``ValueError`` unless :attr:`numpy_ready`. Where a capsule's axis
        enters a box the depth comes from Drake (:func:`armlab.collision.capsules.capsule_box`); with ``depth``
        False it is left at −radius, above the true signed distance (what a contact test needs: it is < 0)."""
        if not self.numpy_ready:
            raise ValueError(f"{self.arm.name}: a pair has a cylinder, mesh or a box on a link: only Drake computes it")
        q = as_batch(q, self.arm.n)
        flat = q.reshape(-1, self.arm.n)
        G = len(self._geometry_pairs)
        distance, point_a, point_b = np.empty((len(flat), G)), np.empty((len(flat), G, 3)), np.empty((len(flat), G, 3))
        A = [self._parts[a] for a, _ in self._geometry_pairs]
        B = [self._parts[b] for _, b in self._geometry_pairs]
        geometries = list(dict.fromkeys(g for pair in self._geometry_pairs for g in pair))  # each part's ends once
        index = {g: k for k, g in enumerate(geometries)}
        ia, ib = (np.array([index[pair[k]] for pair in self._geometry_pairs], dtype=np.intp) for k in (0, 1))
        rA, rB = np.array([p.radius for p in A]), np.array([p.radius for p in B])
        floor = np.array([p.kind == "floor" for p in B], dtype=bool)
        box = np.array([p.kind == "box" for p in B], dtype=bool)
        capsule = ~(floor | box)
        for block in blocks(len(flat)) if G else []:
            frames = self.arm.table.frames(flat[block])  # (B, n+2, 4, 4)
            ends = [self._ends(frames, self._parts[g]) for g in geometries]
            E0, E1 = np.stack([e[0] for e in ends], axis=1), np.stack([e[1] for e in ends], axis=1)
            P0, P1, Q0, Q1 = E0[:, ia], E1[:, ia], E0[:, ib], E1[:, ib]
            size = len(frames)
            d, pa, pb = np.empty((size, G)), np.empty((size, G, 3)), np.empty((size, G, 3))
            if capsule.any():
                d[:, capsule], pa[:, capsule], pb[:, capsule] = capsule_capsule(
                    P0[:, capsule], P1[:, capsule], rA[capsule], Q0[:, capsule], Q1[:, capsule], rB[capsule])
            if floor.any():
                fd, fa, fb = capsule_floor(P0[:, floor], P1[:, floor], rA[floor], Q0[:, floor], Q1[:, floor])
                d[:, floor], pa[:, floor], pb[:, floor] = fd, fa, fb
            if box.any():
                X = np.stack([frames[:, p.frame] @ p.X for p in B if p.X is not None], axis=1)
                half = np.array([p.a for p in B if p.kind == "box"])
                bd, ba, bb, inside = capsule_box(P0[:, box], P1[:, box], rA[box], X, half)
                d[:, box], pa[:, box], pb[:, box] = bd, ba, bb
                for k, j in np.argwhere(inside) if depth else ():  # the axis enters the box: Drake's depth
                    column = np.flatnonzero(box)[j]
                    d[k, column], pa[k, column], pb[k, column] = self._drake_at(flat[block][k], column)
            distance[block], point_a[block], point_b[block] = d, pa, pb
        return self._reduce(q, distance, point_a, point_b)

    def _drake_at(self, q: NDArray[np.float64], pair: int) -> tuple[float, NDArray, NDArray]:
        """Drake's signed distance and closest points of geometry pair ``pair`` at one ``q``."""
        self.plant.SetPositions(self._plant_context, q)
        query = self.scene_graph.get_query_output_port().Eval(self._scene_context)
        return self._drake_pair(query, *self._geometry_pairs[pair])

    @staticmethod
    def _ends(frames: NDArray[np.float64], part: Part) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """A part's two points in the world for each sample ``(B, 3)`` each (a floor: its point and its normal)."""
        R, p = frames[:, part.frame, :3, :3], frames[:, part.frame, :3, 3]
        if part.kind == "floor":
            return R @ part.a + p, R @ part.b
        return R @ part.a + p, R @ part.b + p
