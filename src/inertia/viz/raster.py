"""A small renderer for the flip video: shaded triangles and lines by the painter's algorithm.

Pillow fills the polygons (C speed); NumPy projects, culls, shades and sorts them.  Faces
turned away from the camera are dropped and the rest drawn far to near, which is exact for
convex parts and close enough for a body seen whole.  Lines and discs (the angular-momentum
arrow, the principal axes, the six points) are cut in short pieces; a ray cast toward the
viewer decides whether the body hides each piece, which is then drawn before the body (and
covered by it) or after it.  Frames are drawn at twice the size and halved
(anti-aliasing).  The projection is orthographic; the screen's up is a given world
direction (the angular momentum, in the video).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: supersampling factor (drawn at this multiple of the output size, then reduced)
SUPERSAMPLE = 2


@dataclass(frozen=True)
class Camera:
    """Orthographic camera: world unit vectors ``right``, ``up``, ``toward`` (the viewer),
    ``center`` (x, y) in output pixels of the world origin, ``scale`` output pixels per metre."""

    right: np.ndarray
    up: np.ndarray
    toward: np.ndarray
    center: tuple
    scale: float

    @staticmethod
    def looking_at_origin(up_world, *, center, scale, azimuth_deg: float = 35.0, elevation_deg: float = 16.0):
        """A camera whose screen-up is ``up_world``, turned ``azimuth_deg`` about it and raised
        ``elevation_deg`` above the plane normal to it."""
        up = np.asarray(up_world, float) / np.linalg.norm(up_world)
        seed = np.eye(3)[int(np.argmin(np.abs(up)))]
        h = seed - up * (seed @ up)
        h /= np.linalg.norm(h)
        side = np.cross(up, h)
        a, e = np.radians(azimuth_deg), np.radians(elevation_deg)
        horizontal = np.cos(a) * h + np.sin(a) * side
        toward = np.cos(e) * horizontal + np.sin(e) * up
        screen_up = up - toward * (up @ toward)
        screen_up /= np.linalg.norm(screen_up)
        return Camera(np.cross(screen_up, toward), screen_up, toward, tuple(center), float(scale))

    def project(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Supersampled pixel coordinates (..., 2) and depth (...; larger is nearer) of world points."""
        P = np.asarray(points, float)
        s = SUPERSAMPLE
        xy = np.stack([self.center[0] + self.scale * (P @ self.right),
                       self.center[1] - self.scale * (P @ self.up)], axis=-1) * s
        return xy, P @ self.toward


@dataclass
class Overlay:
    """Lines and discs to paint among the faces: each a world position for its depth."""

    lines: list = field(default_factory=list)   # (p0, p1, rgb, width_px)
    discs: list = field(default_factory=list)   # (p, radius_px, rgb)
    polys: list = field(default_factory=list)   # ((n, 3) world points, rgb): arrow heads

    def arrow(self, start, end, rgb, width_px: float, head_px: float, camera: Camera, *, pieces: int = 12):
        """An arrow cut into ``pieces`` so the body can hide part of it; a flat head facing the camera."""
        start, end = np.asarray(start, float), np.asarray(end, float)
        d = end - start
        head = head_px / camera.scale
        shaft_end = end - d / np.linalg.norm(d) * head
        ts = np.linspace(0.0, 1.0, pieces + 1)
        for a, b in zip(ts[:-1], ts[1:]):
            self.lines.append((start + a * (shaft_end - start), start + b * (shaft_end - start), rgb, width_px))
        side = np.cross(d, camera.toward)
        side = side / (np.linalg.norm(side) or 1.0) * head * 0.45
        self.polys.append((np.array([end, shaft_end + side, shaft_end - side]), rgb))


def shade(normals, base_rgb, camera: Camera) -> np.ndarray:
    """Face colours (F, 3) uint8: ambient + Lambert + a Blinn highlight, light from upper left."""
    light = -0.45 * camera.right + 0.75 * camera.up + 0.5 * camera.toward
    light /= np.linalg.norm(light)
    half = light + camera.toward
    half /= np.linalg.norm(half)
    diffuse = np.clip(normals @ light, 0.0, None)
    spec = np.clip(normals @ half, 0.0, None) ** 30
    rgb = np.asarray(base_rgb, float) * (0.30 + 0.70 * diffuse)[:, None] + 110.0 * spec[:, None]
    return np.clip(rgb, 0, 255).astype(np.uint8)


def face_normals(vertices, faces) -> np.ndarray:
    V = np.asarray(vertices, float)
    n = np.cross(V[faces[:, 1]] - V[faces[:, 0]], V[faces[:, 2]] - V[faces[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def hidden(points, vertices_world, faces, camera: Camera) -> np.ndarray:
    """Whether each world point is behind a face, seen from the camera: a ray cast toward the
    viewer (Moller-Trumbore) against the faces whose screen box holds the point."""
    P = np.asarray(points, float).reshape(-1, 3)
    if vertices_world is None or not len(faces) or not len(P):
        return np.zeros(len(P), bool)
    xy, _ = camera.project(vertices_world)
    tri = xy[faces]                                   # (F, 3, 2)
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    pxy, _ = camera.project(P)
    pi, fi = np.nonzero(np.all((lo[None] <= pxy[:, None]) & (pxy[:, None] <= hi[None]), axis=2))
    A, B, C = (vertices_world[faces[fi, i]] for i in range(3))
    e1, e2 = B - A, C - A
    d = camera.toward
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    sv = P[pi] - A
    u = np.einsum("ij,ij->i", sv, h) * inv
    qv = np.cross(sv, e1)
    v = (qv @ d) * inv
    t = np.einsum("ij,ij->i", qv, e2) * inv
    hit = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & ok
    return np.bincount(pi[hit], minlength=len(P)) > 0


def part_order(vertices_world, faces, face_part, visible, camera: Camera, *, samples: int = 48) -> np.ndarray:
    """Drawing rank of each part, back to front: part B goes after part A when rays from A's
    visible faces toward the viewer hit B more often than the other way round.  Exact for
    convex parts that neither interpenetrate nor overlap in a cycle; within a part, culling
    and depth order do the rest."""
    n_parts = int(face_part.max()) + 1
    if n_parts == 1:
        return np.zeros(1, np.int64)
    V = vertices_world
    hits = np.zeros((n_parts, n_parts))          # hits[a, b]: rays from a blocked by b
    for a in range(n_parts):
        mine = np.flatnonzero(visible & (face_part == a))
        if not len(mine):
            continue
        pick = mine[np.linspace(0, len(mine) - 1, min(samples, len(mine))).astype(int)]
        centers = V[faces[pick]].mean(axis=1)
        for b in range(n_parts):
            if b != a:
                hits[a, b] = hidden(centers, V, faces[face_part == b], camera).sum()
    _, depth = camera.project(V)
    mean_depth = np.array([depth[faces[face_part == k]].mean() for k in range(n_parts)])
    # a part's "in front" score: how often it blocks others minus how often it is blocked
    score = hits.sum(axis=0) - hits.sum(axis=1) + 1e-6 * mean_depth / (np.abs(mean_depth).max() or 1.0)
    rank = np.empty(n_parts, np.int64)
    rank[np.argsort(score, kind="stable")] = np.arange(n_parts)
    return rank


def paint(image, camera: Camera, vertices_world=None, faces=None, face_rgb=None, overlay: Overlay | None = None,
          face_part=None):
    """Draw the visible faces far to near and the overlay into the supersampled Pillow ``image``;
    overlay pieces the body hides (ray cast) go first, the others last.  With ``face_part``
    (connected part of each face) whole parts are drawn back to front (:func:`part_order`)."""
    from PIL import ImageDraw

    draw = ImageDraw.Draw(image)
    s = SUPERSAMPLE
    overlay = overlay or Overlay()
    items, where = [], []     # (kind, payload), world point deciding visibility and order
    if overlay.lines:
        ends = np.array([(p0, p1) for p0, p1, _, _ in overlay.lines], float)      # (n, 2, 3)
        xy, _ = camera.project(ends)
        for (_, _, rgb, w), seg in zip(overlay.lines, xy.reshape(-1, 4).tolist()):
            items.append((1, (seg, rgb, int(round(w * s)))))
        where += list(ends.mean(axis=1))
    if overlay.discs:
        centers = np.array([p for p, _, _ in overlay.discs], float)
        xy, _ = camera.project(centers)
        for (_, r, rgb), c in zip(overlay.discs, xy.tolist()):
            items.append((2, (c, r * s, rgb)))
        where += list(centers)
    for pts, rgb in overlay.polys:
        xy, _ = camera.project(pts)
        items.append((0, (xy.ravel().tolist(), rgb)))
        where.append(np.asarray(pts, float).mean(axis=0))
    where = np.array(where).reshape(-1, 3)
    behind = hidden(where, vertices_world, faces, camera)
    order = np.argsort(where @ camera.toward, kind="stable")     # far to near
    items, behind = [items[i] for i in order], behind[order]
    _draw_items(draw, [it for it, b in zip(items, behind) if b])
    if vertices_world is not None and len(faces):
        n = face_normals(vertices_world, faces)
        visible = n @ camera.toward > 0.0
        xy, depth = camera.project(vertices_world)
        colors = shade(n[visible], face_rgb[visible], camera)
        F = faces[visible]
        key = depth[F].mean(axis=1)
        if face_part is not None:
            rank = part_order(vertices_world, faces, face_part, visible, camera)
            key = key + (key.max() - key.min() + 1.0) * rank[face_part[visible]]
        order = np.argsort(key)
        tri = xy[F[order]].reshape(len(order), 6).tolist()
        for t, c in zip(tri, map(tuple, colors[order].tolist())):
            draw.polygon(t, fill=c, outline=c)
    _draw_items(draw, [it for it, b in zip(items, behind) if not b])


def _draw_items(draw, items) -> None:
    s = SUPERSAMPLE
    for kind, p in items:
        if kind == 0:
            draw.polygon(p[0], fill=p[1])
        elif kind == 1:
            draw.line(p[0], fill=p[1], width=p[2])
        else:
            (x, y), r, rgb = p
            draw.ellipse((x - r, y - r, x + r, y + r), fill=rgb, outline=(40, 40, 40), width=s)
