"""The ``clearance`` finding: the smallest distance between every pair that may not touch.

Every pair of :class:`problems.SceneCollision` (robot against scene objects, robot against
itself, carried objects against the others; pairs the scene allows during some phases are off
in those phases) is measured at every sampled instant, the carried objects moved with their
frame from the moment they are taken and left where the frame puts them down. Between two
samples the distance cannot fall faster than the shapes move apart or together: a point
carried by joint i's subtree moves at most ``sum_i |qd_i| * r_i`` [m/s], ``r_i`` an upper
bound of its distance from joint i's origin (the joint offsets down the chain, prismatic
travel included, plus the shape's reach from its joint; 1 for a prismatic joint), so two
shapes close at most twice that. ``|qd_i|`` is bounded on each polynomial segment by its
Bernstein coefficients. With samples ``d_a``, ``d_b`` ``h`` apart and that speed ``V``, the
distance between them is at least ``(d_a + d_b - 2 V h) / 2``; an interval whose bound falls
below the required clearance while its ends do not is halved until it does not (or a sample
fails). The finding's value is the smallest sampled distance (its pair and time); it passes
when the bound over the whole trajectory keeps the scene's ``margin`` (its margin is that
bound less the margin; its ratio, :data:`RATIO_SCALE`).

Example::

    evaluations.append(clearance_check(SceneCollision(robot, scene), ctx))
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.polynomials import bernstein, evaluate_piecewise, segment_index
from optraj.planners.checker.report import Finding
from optraj.planners.checker.task import Evaluation, missing_findings, task_finding
from optraj.problems.scene_distances import SceneCollision

__all__ = ["MAX_HALVINGS", "RATIO_SCALE", "clearance_check", "clearance_pair", "joint_reach"]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Halvings of one sample interval before its bound is taken as it stands.
MAX_HALVINGS = 12
#: The finding's ratio is 1 at the required clearance and grows by 1 for each RATIO_SCALE [m]
#: (or each required clearance, if larger) the smallest distance falls short of it; 0 when it
#: is clear by that much or more. Finite even where shapes overlap.
RATIO_SCALE = 0.01


def clearance_check(shapes: SceneCollision, ctx: CheckContext) -> Evaluation:
    """``clearance`` over the whole trajectory (see the module docstring)."""
    required = float(shapes.scene.margin)
    times = ctx.grid
    windows, missing = _windows(shapes, ctx)
    if missing:
        return missing_findings([("clearance", required, "m")], missing)

    def evaluate() -> list[Finding]:
        run = _Run(shapes, ctx, windows)
        return [run.finding(times, required)]

    return evaluate


def _windows(shapes: SceneCollision, ctx: CheckContext) -> tuple[list[tuple[float, float]], str]:
    """Each attachment's (start, end) [s], or a reason it cannot be placed."""
    spans = []
    for attachment in shapes.scene.attachments:
        start = _instant(ctx, attachment.start, first=True)
        end = _instant(ctx, attachment.end, first=False)
        if start is None or end is None:
            return [], (
                f"attachment of {attachment.object!r}: phase {attachment.start!r} or "
                f"{attachment.end!r} missing"
            )
        spans.append((start, max(start, end)))
    return spans, ""


def _instant(ctx: CheckContext, when: float | str, *, first: bool) -> float | None:
    if isinstance(when, str):
        phase = ctx.phase(when)
        return None if phase is None else (phase.t_start if first else phase.t_end)
    return min(float(when), ctx.duration)


class _Run:
    """One clearance evaluation: distances at instants, and the speed bound per segment."""

    def __init__(
        self, shapes: SceneCollision, ctx: CheckContext, windows: list[tuple[float, float]]
    ) -> None:
        self.shapes = shapes
        self.ctx = ctx
        self.windows = windows
        grid = ctx.grid
        q = evaluate_piecewise(ctx.derivatives[0], ctx.knots, grid)
        self._grid_q = dict(zip(grid.tolist(), q, strict=True))
        self.spans = [self._phase_spans(phases) for phases in shapes.windows]
        self._windowed = [k for k, spans in enumerate(self.spans) if spans]
        self._all = np.ones(len(self.spans), dtype=bool)
        # Each carried object's pose in its frame, as it is when it is taken.
        self.offsets: list[FloatArray] = [
            np.asarray(
                np.linalg.inv(shapes.frame_pose(self._q(start), frame)) @ self._object_pose(index),
                dtype=np.float64,
            )
            for (index, frame), (start, _) in zip(shapes.attached, windows, strict=True)
        ]
        self.speed = _segment_speeds(ctx, shapes, self.offsets)
        self._cache: dict[tuple[float, bytes], tuple[float, int]] = {}
        self._released: dict[int, FloatArray] = {}

    def _object_pose(self, index: int) -> FloatArray:
        return np.asarray(self.shapes.geometry.geometryObjects[index].placement.homogeneous)

    def _phase_spans(self, phases: tuple[str, ...]) -> list[tuple[float, float]]:
        found = [self.ctx.phase(name) for name in phases]
        return [(p.t_start, p.t_end) for p in found if p is not None]

    def _q(self, time: float) -> FloatArray:
        if time in self._grid_q:
            return self._grid_q[time]
        at = np.array([min(max(time, 0.0), self.ctx.duration)])
        return evaluate_piecewise(self.ctx.derivatives[0], self.ctx.knots, at)[0]

    def mask(self, time: float) -> BoolArray:
        """The pairs checked at ``time`` [s] (off inside a phase that allows them)."""
        return self.masks(np.array([time]))[0]

    def masks(self, times: FloatArray) -> BoolArray:
        """The pairs checked at each of ``times`` [s], shape (m, pairs)."""
        masks = np.ones((times.size, self._all.size), dtype=bool)
        for k in self._windowed:
            for a, b in self.spans[k]:
                masks[(times >= a) & (times <= b), k] = False
        return masks

    def distance(self, time: float, mask: BoolArray) -> tuple[float, int]:
        """(smallest distance [m], pair index) at ``time`` over the pairs of ``mask``."""
        key = (time, mask.tobytes())
        if key not in self._cache:
            self._cache[key] = self._measure(time, mask)
        return self._cache[key]

    def _measure(self, time: float, mask: BoolArray) -> tuple[float, int]:
        shapes = self.shapes
        q = self._q(time)
        poses = {}
        for (index, frame), (start, end), offset in zip(
            shapes.attached, self.windows, self.offsets, strict=True
        ):
            if time >= end:  # put down: it stays where the frame left it
                if index not in self._released:
                    self._released[index] = shapes.frame_pose(self._q(end), frame) @ offset
                poses[index] = self._released[index]
            elif time >= start:
                poses[index] = shapes.frame_pose(self._q(time), frame) @ offset
        shapes.set_active(mask)
        where = shapes.compute(q, poses)
        if not 0 <= where < shapes.pair_count or not mask[where]:
            return math.inf, -1
        return shapes.pair_distance(where).distance, where

    def finding(self, times: FloatArray, required: float) -> Finding:
        """Sample, bound every interval, halve the doubtful ones, and judge."""
        best = (math.inf, -1, 0.0)  # distance, pair, time
        bound = math.inf
        segment = dict(zip(times.tolist(), segment_index(self.ctx.knots, times), strict=True))
        masks = self.masks(0.5 * (times[:-1] + times[1:]))
        for (a, b), mask in zip(itertools.pairwise(times.tolist()), masks, strict=True):
            speed = 2.0 * float(self.speed[segment[a]])
            low, sampled = self._interval(a, b, mask, speed, required)
            bound = min(bound, low)
            best = min(best, sampled)
        if times.size == 1:
            value, pair = self.distance(float(times[0]), self.mask(float(times[0])))
            best, bound = (value, pair, float(times[0])), value
        value, pair, time = best
        if pair < 0:  # every pair may touch: nothing can fail
            finding = task_finding("clearance", math.inf, required, None, "m", "no pair to check")
            return _with(finding, margin=math.inf, ratio=0.0)
        first, second = self.shapes.pair_names(pair)
        detail = (
            f"{first} to {second}: {value:.4g} m at t = {time:.6g} s; at least {bound:.4g} m "
            "between samples"
        )
        finding = task_finding("clearance", value, required, time, "m", detail)
        margin = min(bound, value) - required
        ratio = max(0.0, 1.0 + (required - value) / max(required, RATIO_SCALE))
        return _with(finding, margin=margin, ratio=ratio)

    def _interval(
        self, a: float, b: float, mask: BoolArray, speed: float, required: float
    ) -> tuple[float, tuple[float, int, float]]:
        """(lower bound [m], smallest sample (distance, pair, time)) over [a, b]."""
        da, pa = self.distance(a, mask)
        db, pb = self.distance(b, mask)
        best = min((da, pa, a), (db, pb, b))
        stack = [(a, da, b, db, 0)]
        low = math.inf
        while stack:
            t0, d0, t1, d1, depth = stack.pop()
            bound = 0.5 * (d0 + d1 - speed * (t1 - t0))
            if bound >= required or min(d0, d1) < required or depth >= MAX_HALVINGS:
                low = min(low, bound, d0, d1)
                continue
            tm = 0.5 * (t0 + t1)
            dm, pm = self.distance(tm, mask)
            best = min(best, (dm, pm, tm))
            stack.extend([(t0, d0, tm, dm, depth + 1), (tm, dm, t1, d1, depth + 1)])
        return low, best


def clearance_pair(finding: Finding) -> tuple[str, str]:
    """The two shapes of a ``clearance`` finding, read back from its detail.

    The detail is written above as ``"<first> to <second>: ..."``; this reads that form.

    Raises:
        InvalidInputError: Not a clearance finding, or one with no pair ("no pair to check").
    """
    head, written, _ = finding.detail.partition(": ")
    first, _, second = head.partition(" to ")
    if finding.name != "clearance" or not written or not first or not second:
        raise InvalidInputError(
            f"not a clearance finding with a pair: {finding.name!r}, {finding.detail!r}",
            name="finding",
        )
    return first, second


def _with(finding: Finding, *, margin: float, ratio: float) -> Finding:
    """``finding`` with another margin and ratio, judged again on that margin."""
    slack = 1e-12
    return replace(finding, margin=margin, ratio=ratio, ok=margin >= -slack)


def joint_reach(shapes: SceneCollision, offsets: list[FloatArray]) -> FloatArray:
    """Per joint, an upper bound of the distance of any moving shape from its origin [m].

    Shapes are the robot's and the carried objects (with ``offsets``, object in frame);
    shape (njoints,), index 0 (the world) unused.
    """
    model = shapes.robot.model
    extent = np.zeros(model.njoints)
    for g in list(shapes.geometry.geometryObjects)[: shapes.robot_count]:
        j = int(g.parentJoint)
        extent[j] = max(extent[j], _reach(g.geometry, g.placement))
    for (index, frame), offset in zip(shapes.attached, offsets, strict=True):
        placed = model.frames[frame].placement * pin.SE3(offset)
        g = shapes.geometry.geometryObjects[index]
        j = int(model.frames[frame].parentJoint)
        extent[j] = max(extent[j], _reach(g.geometry, placed))
    reach = np.zeros(model.njoints)
    for j in range(model.njoints - 1, 0, -1):
        reach[j] = max(reach[j], extent[j])
        parent = int(model.parents[j])
        if parent > 0:
            reach[parent] = max(reach[parent], _offset(model, j) + reach[j])
    return reach


def _reach(shape: object, placement: pin.SE3) -> float:
    shape.computeLocalAABB()  # type: ignore[attr-defined]
    radius = float(shape.aabb_radius)  # type: ignore[attr-defined]
    centre = np.array(shape.aabb_center, dtype=np.float64)  # type: ignore[attr-defined]
    return float(np.linalg.norm(placement.act(centre))) + radius


def _offset(model: pin.Model, j: int) -> float:
    """Largest distance of joint j's origin from its parent's [m] (prismatic travel too)."""
    base = float(np.linalg.norm(model.jointPlacements[j].translation))
    if model.joints[j].shortname().startswith("JointModelP"):
        i = model.joints[j].idx_q
        base += max(abs(model.lowerPositionLimit[i]), abs(model.upperPositionLimit[i]))
    return base


def _segment_speeds(
    ctx: CheckContext, shapes: SceneCollision, offsets: list[FloatArray]
) -> FloatArray:
    """Per segment, a bound of the fastest any shape point moves [m/s], shape (K,)."""
    model = shapes.robot.model
    reach = joint_reach(shapes, offsets)
    weights = np.zeros(ctx.limits.n)
    for j in range(1, model.njoints):
        prismatic = model.joints[j].shortname().startswith("JointModelP")
        weights[model.joints[j].idx_v] = 1.0 if prismatic else reach[j]
    velocity = ctx.derivatives[1]  # (K, d + 1, n)
    width = velocity.shape[1]
    h = np.diff(ctx.knots)
    scaled = velocity * (h[:, None] ** np.arange(width, dtype=float))[:, :, None]
    enclosure = np.einsum("kin,ij->kjn", scaled, bernstein(width - 1))
    peak = np.max(np.abs(enclosure), axis=1)  # (K, n): |qd| on each segment
    return np.asarray(peak @ weights, dtype=float)
