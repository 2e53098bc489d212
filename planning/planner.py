"""Motions that miss the obstacles: a collision-free joint path from A to B, smoothed, then timed as fast as the
limits allow (:func:`plan_path`, ``armlab plan ARM to``).

1. **Search**: RRT-Connect (Kuffner & LaValle, ICRA 2000) in joint space, two trees grown from the start and the goal
   towards seeded random samples within the joint limits, each extension greedy until blocked, the straight
   segment tried first. Seeded (``seed``): the same query gives the same path.
2. **Edges checked densely, with a certificate**: a straight joint segment is free by ``clearance`` (m) when every
   one of its points is: its samples' clearances are computed in batches (:class:`~armlab.collision.model.
   CollisionModel`: numpy's closed forms for capsules, spheres, boxes and floors, Drake's query otherwise), and no
   clearance changes by more than L·|Δq| between samples (L: :meth:`~armlab.collision.model.CollisionModel.
   motion_bound`, twice the farthest any point of the arm moves per unit of each joint), so a piece between two
   samples of clearances d₀, d₁ a distance h apart clears (d₀ + d₁ − L·h)/2. A piece that this does not certify
   is split, in batches, until it is certified or a sample is within the clearance (the edge is blocked). The
   certificate is as exact as the clearances: numpy's are closed forms; where Drake computes a pair (a cylinder,
   a mesh), its GJK distances may be up to ~1 mm above the exact ones (drake#14731).
3. **Shortcutting**: seeded random pairs of the path's points joined straight where that edge is free, then each
   point joined to the farthest one it sees.
4. **Smoothing**: each corner blended by a quadratic Bézier arc tangent to both segments (the path is C¹, at unit
   speed in its parameter s), its size halved until the arc is certified free like an edge (the arc's speed bound
   is exact: its derivative is linear).
5. **Confirmation**: Drake's query (:meth:`~armlab.collision.model.CollisionModel.drake`, ``SceneGraph``'s signed
   distances, not numpy's) at :data:`CONFIRM_SAMPLES` points along the smooth path, each at least the clearance.
6. **Timing**: the smooth path q(s) timed as fast as the limits allow (:func:`armlab.planning.timing.fastest`,
   Drake's Toppra), rest to rest; the timed motion follows the path exactly, so it keeps its clearance.
"""

from __future__ import annotations

import heapq
import itertools
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armlab.bounds import above
from armlab.collision.clearance import as_scene
from armlab.collision.model import CollisionModel
from armlab.limits import check_positive
from armlab.planning.timing import DEFAULT_GRID, fastest

if TYPE_CHECKING:
    from pydrake.trajectories import PiecewisePolynomial

    from armlab.collision.scene import Scene
    from armlab.kinematics.quintic import Motion
    from armlab.models.arm import Arm
    from armlab.planning.timing import Fastest

__all__ = ["CONFIRM_SAMPLES", "NoPathError", "Plan", "Planner", "Roadmap", "Route", "plan_path"]

#: Points along the smooth path at which Drake's query confirms the clearance.
CONFIRM_SAMPLES = 200
#: The longest step of one tree extension (rad, or m for a prismatic joint; Euclidean in joint space).
STEP = 2.0
#: The most pieces one edge is split into before it counts as blocked (its clearance within round-off of the bound).
MAX_PIECES = 1 << 16
#: A curve's first samples (:func:`_first_samples`): one per this much (m) of its possible clearance change, at
#: most this many; then only the pieces not certified are split.
FIRST_SPACING = 0.05
FIRST_SAMPLES = 8
#: Seeded shortcut attempts.
SHORTCUTS = 60


class NoPathError(ValueError):
    """No collision-free path was found within the time budget (the query may have one: a longer budget may)."""


@dataclass(frozen=True)
class Plan:
    """A planned motion: ``waypoints`` ``(k, n)`` (rad, m) of the shortcut path, ``path`` the smooth path q(s) (a
    Drake ``PiecewisePolynomial``, s in rad of joint-space length), ``timed`` its fastest timing
    (:class:`~armlab.planning.timing.Fastest`: ``timed.motion`` to simulate), ``min_clearance`` (m, the smallest of
    every pair along the smooth path by Drake's query at the confirmation samples) and its pair, ``length`` (rad,
    the joint-space length of the smooth path), ``planning_time`` (s, search to confirmation, timing excluded),
    ``nodes`` (the trees' size) and ``samples_checked`` (configurations whose clearances were computed)."""

    waypoints: NDArray[np.float64]
    path: PiecewisePolynomial
    timed: Fastest
    min_clearance: float
    closest_pair: str
    length: float
    planning_time: float
    nodes: int
    samples_checked: int
    clearance: float

    @property
    def motion(self) -> Motion:
        """The timed motion (``armlab.simulate(arm, plan.motion)``)."""
        return self.timed.motion

    @property
    def duration(self) -> float:
        """The timed motion's duration (s)."""
        return self.timed.duration


@dataclass(frozen=True)
class Route:
    """A collision-free path before its timing (:meth:`Planner.route`): ``waypoints`` ``(k, n)``, the smooth
    ``path`` q(s), the trees' size ``nodes``, ``planning_time`` (s; ``search_time`` of it the search's) and the
    configurations ``checked``."""

    waypoints: NDArray[np.float64]
    path: PiecewisePolynomial
    nodes: int
    planning_time: float
    checked: int
    search_time: float


class Planner:
    """Collision-free joint paths of ``arm`` among ``scene``'s obstacles, ``clearance`` (m) from every one and from
    itself: the checks :func:`plan_path` uses (module docstring), one collision model for many queries."""

    def __init__(self, arm: Arm, scene: Scene | str | Path | None = None, clearance: float = 0.0) -> None:
        if not isinstance(clearance, int | float) or isinstance(clearance, bool) or not np.isfinite(clearance) \
                or clearance < 0:  # not a bound: a value the user gave
            raise ValueError(f"clearance = {clearance!r} is not allowed: give a margin ≥ 0 m")
        self.arm, self.clearance = arm, float(clearance)
        self.model = CollisionModel(arm, as_scene(scene))
        self.lipschitz = 2 * self.model.motion_bound()
        if not np.all(np.isfinite(self.lipschitz)):
            raise ValueError(f"{arm.name}: a collision shape's reach is unknown (not a capsule, sphere, box, cylinder "
                             "or mesh): its motion cannot be certified")
        self.lower, self.upper = arm.limit_arrays(unlimited=2 * np.pi)
        self.checked = 0

    # ------------------------------------------------------------------ checks
    def clearances(self, q: ArrayLike) -> NDArray[np.float64]:
        """The smallest clearance over every pair (m) at each configuration of ``q`` ``(m, n)``: ``(m,)``."""
        q = np.asarray(q, dtype=float).reshape(-1, self.arm.n)
        self.checked += len(q)
        distance = self.model.distances(q, depth=False).distance  # a depth below −radius changes no answer
        return distance.min(axis=1) if distance.shape[1] else np.full(len(q), np.inf)

    def free(self, q: ArrayLike) -> NDArray[np.bool_]:
        """Whether each configuration of ``q`` ``(m, n)`` clears by the clearance."""
        return np.logical_not(above(-self.clearances(q), -self.clearance))

    def _certify(self, points: Any, starts: NDArray[np.float64], speed: float) -> bool:
        """Whether the curve ``points(t)`` (t ∈ [0, 1] → ``(m, n)``), whose clearances change at most ``speed`` (m
        per unit t), is free: samples at ``starts`` and 1, each piece not certified split (in one batch a round)
        into as many as its samples' clearances say it needs, until all are certified or a sample is within the
        clearance (module docstring)."""
        t = np.append(starts, 1.0)
        d = self.clearances(points(t))
        margin = self.clearance
        while True:
            if np.any(above(-d, -margin)):
                return False
            h = np.diff(t)
            certified = np.logical_not(above(-(d[:-1] + d[1:] - speed * h) / 2, -margin))
            if np.all(certified):
                return True
            if len(t) > MAX_PIECES:
                return False
            # split each uncertified piece into as many as its two clearances say would certify (2 … 64)
            lo, width = t[:-1][~certified], h[~certified]
            room = (d[:-1] + d[1:])[~certified] - 2 * margin  # > 0: both samples clear the margin
            parts = np.clip(np.ceil(speed * width / np.maximum(room, 1e-300)), 2, 64).astype(int)
            middle = np.concatenate([a + w * np.arange(1, k) / k for a, w, k in zip(lo, width, parts, strict=True)])
            dm = self.clearances(points(middle))
            t_new = np.concatenate([t, middle])
            order = np.argsort(t_new, kind="stable")
            t, d = t_new[order], np.concatenate([d, dm])[order]

    def edge_free(self, a: ArrayLike, b: ArrayLike) -> bool:
        """Whether the straight joint segment from ``a`` to ``b`` (each ``(n,)``) clears by the clearance at every
        point (certified: module docstring)."""
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        speed = float(self.lipschitz @ np.abs(b - a))  # clearance change per unit t, at most
        return self._certify(lambda t: a + np.asarray(t)[:, None] * (b - a), _first_samples(speed), speed)

    def arc_free(self, p: NDArray, w: NDArray, r: NDArray) -> bool:
        """Whether the quadratic Bézier arc p → r with control point ``w`` clears by the clearance (its speed
        B'(t) = 2((1 − t)(w − p) + t(r − w)) is at most its larger end's, the bound used)."""
        speed = 2 * max(float(self.lipschitz @ np.abs(w - p)), float(self.lipschitz @ np.abs(r - w)))
        def points(t: ArrayLike) -> NDArray[np.float64]:
            t = np.asarray(t)[:, None]
            return (1 - t) ** 2 * p + 2 * t * (1 - t) * w + t**2 * r

        return self._certify(points, _first_samples(speed), speed)

    # ------------------------------------------------------------------ search
    def endpoint(self, q: ArrayLike, which: str) -> NDArray[np.float64]:
        """``q`` ``(n,)`` as a query's start or goal (``which`` names it in messages): within the joint limits and
        clear of the obstacles and the arm itself by the clearance, else a one-line ``ValueError``."""
        q = self.arm.check_q(q, which)
        if q.ndim != 1:
            raise ValueError(f"{which} has shape {q.shape}: give one configuration of {self.arm.n} joint values")
        found = self.model.distances(q)
        j = int(np.argmin(found.distance)) if found.distance.size else -1
        if j >= 0 and above(-float(found.distance[j]), -self.clearance):
            touching = found.distance[j] < 0  # not a bound: the wording
            state = "in contact" if touching else f"within the clearance {self.clearance * 1e3:g} mm"
            raise ValueError(f"{which} is {state}: {found.names()[j]} at {found.distance[j] * 1e3:+.4g} mm; give a "
                             "configuration clear of the obstacles and of the arm itself")
        return q

    def search(self, q0: NDArray[np.float64], qf: NDArray[np.float64], rng: np.random.Generator,
               deadline: float) -> tuple[list[NDArray[np.float64]], int]:
        """RRT-Connect from ``q0`` to ``qf`` (both free) until ``deadline`` (``time.perf_counter``): the path's
        points and the trees' size; :class:`NoPathError` at the deadline."""
        if self.edge_free(q0, qf):
            return [q0, qf], 2
        trees = [([q0], [-1]), ([qf], [-1])]  # (nodes, parent index) grown from the start and from the goal
        while time.perf_counter() < deadline:
            sample = rng.uniform(self.lower, self.upper)
            grow, other = trees
            reached = self._extend(grow, sample, once=True)
            if reached is not None:
                joined = self._extend(other, grow[0][reached], once=False)
                if joined is not None and np.array_equal(other[0][joined], grow[0][reached]):
                    path = self._trace(grow, reached)[::-1] + self._trace(other, joined)[1:]
                    if grow[0][0] is not q0:  # grown from the goal: the path runs goal to start
                        path = path[::-1]
                    return path, len(grow[0]) + len(other[0])
            trees = [other, grow]  # alternate, as RRT-Connect does
        raise NoPathError(f"{self.arm.name}: no collision-free path found within the time budget "
                          f"({len(trees[0][0]) + len(trees[1][0])} nodes): give a longer --budget, a smaller "
                          "--clearance, or check that the goal is reachable around the obstacles")

    def _extend(self, tree: tuple[list[NDArray], list[int]], target: NDArray, once: bool) -> int | None:
        """Grow ``tree`` from its node nearest ``target`` towards it by steps of :data:`STEP` (one step if
        ``once``, else until reached or blocked); the index of the last node added, ``None`` if none was."""
        nodes, parents = tree
        nearest = int(np.argmin(np.linalg.norm(np.asarray(nodes) - target, axis=1)))
        added = None
        while True:
            start = nodes[nearest]
            gap = target - start
            distance = float(np.linalg.norm(gap))
            if distance <= 1e-12:  # not a bound: the target reached
                return added
            end = target if distance <= STEP else start + gap * (STEP / distance)  # not a bound: the step length
            if not self.edge_free(start, end):
                return added
            nodes.append(end)
            parents.append(nearest)
            nearest = added = len(nodes) - 1
            if once or end is target:
                return added

    @staticmethod
    def _trace(tree: tuple[list[NDArray], list[int]], index: int) -> list[NDArray[np.float64]]:
        """The tree's nodes from ``index`` back to its root."""
        nodes, parents = tree
        out = []
        while index >= 0:
            out.append(nodes[index])
            index = parents[index]
        return out

    def shortcut(self, path: list[NDArray[np.float64]], rng: np.random.Generator) -> list[NDArray[np.float64]]:
        """``path`` shortened: :data:`SHORTCUTS` seeded random pairs joined where the edge is free, then each point
        joined to the farthest later one it sees."""
        path = list(path)
        for _ in range(SHORTCUTS):
            if len(path) < 3:
                break
            i, j = sorted(rng.choice(len(path), 2, replace=False))
            if j - i > 1 and self.edge_free(path[i], path[j]):
                path = path[:i + 1] + path[j:]
        out, i = [path[0]], 0
        while i < len(path) - 1:
            j = next(j for j in range(len(path) - 1, i, -1) if j == i + 1 or self.edge_free(path[i], path[j]))
            out.append(path[j])
            i = j
        return out

    def smooth(self, waypoints: list[NDArray[np.float64]]) -> PiecewisePolynomial:
        """The C¹ path through the straight pieces of ``waypoints``, each corner blended by a certified quadratic
        arc (module docstring), as a Drake ``PiecewisePolynomial`` q(s) at unit speed, s in joint-space length."""
        points = [np.asarray(p, dtype=float) for p in waypoints]
        lengths = [float(np.linalg.norm(b - a)) for a, b in itertools.pairwise(points)]
        blends = []
        for k in range(1, len(points) - 1):
            size = 0.4 * min(lengths[k - 1], lengths[k])
            w = points[k]
            into, out = (w - points[k - 1]) / lengths[k - 1], (points[k + 1] - w) / lengths[k]
            for _ in range(30):  # halved until certified; a corner that takes none is a stop (size 0)
                if self.arc_free(w - size * into, w, w + size * out):
                    break
                size /= 2
            else:
                size = 0.0
            blends.append(size)
        sizes = [0.0, *blends, 0.0]
        directions = [(b - a) / length for a, b, length in zip(points[:-1], points[1:], lengths, strict=True)]
        knots = [(0.0, points[0], directions[0])]  # (s, q, q'(s)) at each break
        s = 0.0
        for k, u in enumerate(directions):
            start, end = points[k] + sizes[k] * u, points[k + 1] - sizes[k + 1] * u
            if k > 0 and sizes[k] > 0:  # the arc from the previous piece's end, at unit speed: 2·size long
                s += 2 * sizes[k]
                knots.append((s, start, u))
            elif k > 0:  # a corner without an arc: the path stops there (q' = 0)
                knots[-1] = (knots[-1][0], knots[-1][1], np.zeros_like(u))
            s += float(np.linalg.norm(end - start))
            knots.append((s, end, u))
        return _hermite([k[0] for k in knots], [k[1] for k in knots], [k[2] for k in knots])

    def route(self, q0: ArrayLike, qf: ArrayLike, seed: int = 0, budget: float = 5.0,
              roadmap: Roadmap | None = None) -> Route:
        """The collision-free smooth path from ``q0`` to ``qf``, untimed and unconfirmed: search, shortcutting and
        smoothing (module docstring, steps 1-4), within ``budget`` s of search; with a ``roadmap`` (of this planner)
        its shortest free path instead of the search (:class:`Roadmap`)."""
        budget = check_positive(budget, "budget", "s", "give the planning time budget in seconds (> 0)")
        began = time.perf_counter()
        self.checked = 0
        start, goal = self.endpoint(q0, "the start"), self.endpoint(qf, "the goal")
        rng = np.random.default_rng(seed)
        if roadmap is not None:
            if roadmap.planner is not self:
                raise ValueError("the roadmap was built by another planner (another arm, scene or clearance)")
            found, nodes = roadmap.path(start, goal), len(roadmap.nodes)
        else:
            found, nodes = self.search(start, goal, rng, began + budget)
        searched = time.perf_counter() - began
        waypoints = self.shortcut(found, rng)
        path = self.smooth(waypoints)
        return Route(np.array(waypoints), path, nodes, time.perf_counter() - began, self.checked, searched)

    def plan(self, q0: ArrayLike, qf: ArrayLike, seed: int = 0, budget: float = 5.0, roadmap: Roadmap | None = None,
             **timing: Any) -> Plan:
        """The collision-free, smooth, confirmed, timed motion from ``q0`` to ``qf`` (module docstring: :meth:`route`,
        then Drake's confirmation and the timing); ``timing``: the limits of
        :func:`armlab.planning.timing.fastest` (``velocity``, ``acceleration``, ``effort``, ``grid`` …)."""
        route = self.route(q0, qf, seed, budget, roadmap)
        path = route.path
        s = np.linspace(path.start_time(), path.end_time(), CONFIRM_SAMPLES)
        confirmed = self.model.drake(np.array([path.value(t)[:, 0] for t in s]))
        least, closest = float("inf"), ""
        if confirmed.distance.size:
            pair = int(np.argmin(confirmed.distance.min(axis=0)))
            least, closest = float(confirmed.distance[:, pair].min()), confirmed.names()[pair]
        if above(-least, -self.clearance):
            raise RuntimeError(f"{self.arm.name}: Drake's query finds {closest} at {least * 1e3:+.4g} mm on the "
                               "certified path: armlab's numpy clearances disagree")
        timed = fastest(self.arm, path, **{"grid": DEFAULT_GRID, **timing})
        return Plan(route.waypoints, path, timed, least, closest, float(path.end_time() - path.start_time()),
                    route.planning_time, route.nodes, route.checked, self.clearance)


class Roadmap:
    """A lazy probabilistic roadmap (Bohlin & Kavraki's Lazy PRM, ICRA 2000) of one planner's arm and scene, for many
    queries in it: ``nodes`` seeded random free configurations, each joined to its ``neighbours`` nearest (joint-space
    distance), the edges checked only when a query's shortest path uses them (certified as :meth:`Planner.edge_free`
    does) and remembered, blocked or free, for the next queries. ``Planner.route(…, roadmap=)`` or
    ``plan_path(…, roadmap=)`` use it instead of the tree search."""

    def __init__(self, planner: Planner, nodes: int = 400, neighbours: int = 10, seed: int = 0) -> None:
        for value, name in ((nodes, "nodes"), (neighbours, "neighbours")):
            if not isinstance(value, int) or isinstance(value, bool) or value < 2:
                raise ValueError(f"{name} = {value!r} is not allowed: a whole number ≥ 2")
        self.planner = planner
        rng = np.random.default_rng(seed)
        found: list[NDArray[np.float64]] = []
        for _ in range(1000):  # batches of samples until enough are free
            q = rng.uniform(planner.lower, planner.upper, (max(64, nodes), planner.arm.n))
            found.extend(q[planner.free(q)])
            if len(found) >= nodes:
                break
        if len(found) < nodes:
            raise ValueError(f"{planner.arm.name}: fewer than {nodes} free configurations found: the scene leaves "
                             "the arm almost no room")
        self.nodes = np.array(found[:nodes])
        self.neighbours = neighbours
        self._near = self._nearest(self.nodes)
        self._verdict: dict[tuple[int, int], bool] = {}

    @property
    def verdicts(self) -> dict[tuple[int, int], bool]:
        """The roadmap edges checked so far (node index pairs, the lower first) and whether each is free."""
        return dict(self._verdict)

    def _nearest(self, points: NDArray[np.float64]) -> NDArray[np.intp]:
        """The indices of each point's :attr:`neighbours` nearest roadmap nodes (itself excluded) ``(m, k)``."""
        gaps = np.linalg.norm(points[:, None, :] - self.nodes[None, :, :], axis=-1)
        gaps[gaps == 0] = np.inf
        return np.argsort(gaps, axis=1)[:, :self.neighbours]

    def _free(self, a: int, b: int, points: NDArray[np.float64]) -> bool:
        key = (min(a, b), max(a, b))
        if key not in self._verdict or key[1] >= len(self.nodes):  # a query's own edges are not remembered
            verdict = self.planner.edge_free(points[a], points[b])
            if key[1] >= len(self.nodes):
                return verdict
            self._verdict[key] = verdict
        return self._verdict[key]

    def path(self, q0: NDArray[np.float64], qf: NDArray[np.float64]) -> list[NDArray[np.float64]]:
        """The shortest path from ``q0`` to ``qf`` (both free) through the roadmap whose edges are free, checking
        the edges of each shortest candidate in turn (Dijkstra's search); :class:`NoPathError` when the free edges
        do not connect them."""
        if self.planner.edge_free(q0, qf):
            return [q0, qf]
        N = len(self.nodes)
        points = np.vstack([self.nodes, q0, qf])
        ends = self._nearest(np.stack([q0, qf]))
        graph: dict[int, set[int]] = {i: set(map(int, row)) for i, row in enumerate(self._near)}
        for i in range(N):
            for j in self._near[i]:
                graph[int(j)].add(i)
        graph[N], graph[N + 1] = set(map(int, ends[0])), set(map(int, ends[1]))
        for end, row in ((N, ends[0]), (N + 1, ends[1])):
            for j in row:
                graph[int(j)].add(end)
        blocked: set[tuple[int, int]] = {key for key, free in self._verdict.items() if not free}
        while True:
            best, back = {N: 0.0}, {N: -1}
            heap = [(0.0, N)]
            while heap:
                cost, i = heapq.heappop(heap)
                if i == N + 1 or cost > best.get(i, np.inf):
                    if i == N + 1:
                        break
                    continue
                for j in graph[i]:
                    if (min(i, j), max(i, j)) in blocked:
                        continue
                    step = cost + float(np.linalg.norm(points[j] - points[i]))
                    if step < best.get(j, np.inf):
                        best[j], back[j] = step, i
                        heapq.heappush(heap, (step, j))
            if N + 1 not in back:
                raise NoPathError(f"{self.planner.arm.name}: the roadmap's free edges do not join the start to the "
                                  f"goal ({N} nodes): build it with more nodes or neighbours")
            route = [N + 1]
            while back[route[-1]] >= 0:
                route.append(back[route[-1]])
            route.reverse()
            bad = next(((a, b) for a, b in itertools.pairwise(route) if not self._free(a, b, points)), None)
            if bad is None:
                return [points[i] for i in route]
            blocked.add((min(bad), max(bad)))


def _first_samples(speed: float) -> NDArray[np.float64]:
    """Where a curve's check starts (t ∈ [0, 1), the end added): a sample every :data:`FIRST_SPACING` m of the
    most its clearance can change (``speed``, m per unit t), at most :data:`FIRST_SAMPLES`; the certificate splits
    the pieces it cannot certify (far from everything, a coarse piece certifies; near something, it is split)."""
    pieces = int(min(FIRST_SAMPLES, max(1, np.ceil(speed / FIRST_SPACING))))
    return np.linspace(0.0, 1.0, pieces + 1)[:-1]


def _hermite(breaks: list[float], values: list[NDArray], slopes: list[NDArray]) -> PiecewisePolynomial:
    """Drake's cubic Hermite through ``values`` at ``breaks`` with ``slopes``: exactly each straight piece and each
    quadratic arc (the unique cubic with those ends and end slopes)."""
    from pydrake.trajectories import PiecewisePolynomial

    return PiecewisePolynomial.CubicHermite(breaks, [np.asarray(v, dtype=float).reshape(-1, 1) for v in values],
                                            [np.asarray(v, dtype=float).reshape(-1, 1) for v in slopes])


def plan_path(arm: Arm, q0: ArrayLike, qf: ArrayLike, scene: Scene | str | Path | None = None,
              clearance: float = 0.0, seed: int = 0, budget: float = 5.0, **timing: Any) -> Plan:
    """A motion of ``arm`` from ``q0`` to ``qf`` (each ``(n,)``, rad and m) that clears ``scene``'s obstacles and
    the arm itself by ``clearance`` (m) at every point, as fast as the limits allow (:class:`Plan`; module
    docstring). ``seed``: the random search's seed (the same query, the same plan); ``budget``: the search's time
    (s). ``timing``: :func:`armlab.planning.timing.fastest`'s limits (``velocity``, ``acceleration``, ``effort``,
    ``drives``, ``grid`` …). One-line ``ValueError`` for a start or goal outside the limits, in contact or within
    the clearance, a bad clearance or budget; :class:`NoPathError` when the budget runs out."""
    return Planner(arm, scene, clearance).plan(q0, qf, seed=seed, budget=budget, **timing)
