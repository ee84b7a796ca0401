"""Chamfer matching in numpy: the small matcher the own-method examples share.

An observation's wall segments (observer frame: x ahead, y left, metres) are sampled every
`step_m`; for every orientation of the grid and every cell, the score is the mean over the samples
of exp(-d^2 / (2 sigma^2)), d the distance from the sample (placed in the world by the cell and
the orientation) to the nearest wall. Cells nearer a wall than `clearance_m` score 0. It is a
teaching example (no scale handling, no free-space term), not a method from the papers.
"""
import numpy as np


def sample_points(segments, step_m=0.25, max_points=96):
    """Points along (N, 4) segments [ax, ay, bx, by], at most max_points (evenly thinned)."""
    pts = []
    for ax, ay, bx, by in np.asarray(segments, dtype=float).reshape(-1, 4):
        n = max(1, int(np.hypot(bx - ax, by - ay) / step_m))
        t = (np.arange(n) + 0.5) / n
        pts.append(np.stack([ax + t * (bx - ax), ay + t * (by - ay)], axis=1))
    if not pts:
        return np.zeros((0, 2))
    p = np.concatenate(pts)
    if len(p) > max_points:
        p = p[np.linspace(0, len(p) - 1, max_points).round().astype(int)]
    return p


def chamfer_posterior(distance_m, grid, segments, sigma_m=0.2, clearance_m=0.2):
    """Scores (yaw, y, x) float32 on `grid` (dict: resolution_m, width_px, height_px, yaw_deg);
    distance_m is (height_px, width_px): metres from each cell centre to the nearest wall."""
    h, w = grid["height_px"], grid["width_px"]
    res = grid["resolution_m"]
    assert distance_m.shape == (h, w), (distance_m.shape, (h, w))
    likelihood = np.exp(-0.5 * (distance_m / sigma_m) ** 2).astype(np.float32)
    points = sample_points(segments)
    out = np.zeros((len(grid["yaw_deg"]), h, w), np.float32)
    if len(points) == 0:
        return out
    # Pad so every shifted window stays inside (outside the grid: no wall, likelihood 0).
    reach = int(np.ceil(np.linalg.norm(points, axis=1).max() / res)) + 1
    padded = np.zeros((h + 2 * reach, w + 2 * reach), np.float32)
    padded[reach:reach + h, reach:reach + w] = likelihood
    for k, yaw in enumerate(np.radians(grid["yaw_deg"])):
        c, s = np.cos(yaw), np.sin(yaw)
        dx = np.rint((c * points[:, 0] - s * points[:, 1]) / res).astype(int)
        dy = np.rint((s * points[:, 0] + c * points[:, 1]) / res).astype(int)
        acc = out[k]
        for sx, sy in zip(dx, dy):
            acc += padded[reach + sy:reach + sy + h, reach + sx:reach + sx + w]
        acc /= len(points)
    out[:, distance_m < clearance_m] = 0.0
    return out


def wall_distance_from_plan_json(plan, grid):
    """Metres from each cell centre of `grid` to the nearest wall face of a floorcast plan JSON
    (walls as axis segments with a thickness; doors drawn closed), without floorcast."""
    h, w, res = grid["height_px"], grid["width_px"], grid["resolution_m"]
    xs = grid["origin_x_m"] + (np.arange(w) + 0.5) * res
    ys = grid["origin_y_m"] + (np.arange(h) + 0.5) * res
    px, py = np.meshgrid(xs, ys)
    best = np.full((h, w), np.inf)
    for wall in plan["walls"]:
        (ax, ay), (bx, by) = wall["a"], wall["b"]
        vx, vy = bx - ax, by - ay
        length2 = max(vx * vx + vy * vy, 1e-12)
        t = np.clip(((px - ax) * vx + (py - ay) * vy) / length2, 0.0, 1.0)
        d = np.hypot(px - (ax + t * vx), py - (ay + t * vy)) - 0.5 * wall.get("thickness_m", 0.0)
        np.minimum(best, d, out=best)
    return np.maximum(best, 0.0)
