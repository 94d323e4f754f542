"""Finding the crossings of a grid of dark lines on the floor (the paper's calibration pattern).

1. Line pixels: dark, thin structures (black-hat transform), kept where they reach half of the
   strongest line response nearby, so far lines that blur into low contrast are kept too.
2. Cells: the light regions enclosed by lines, each a convex quadrilateral in the image (a wide
   angle lens bends the lines, but not much over one cell).
3. Topology: two cells are neighbours when an edge of one faces an edge of the other across a
   line; walking from cell to cell gives each cell, and each of its corners, grid coordinates.
4. Each crossing, first the mean of the cell corners around it, is refined to sub-pixel
   accuracy where the two lines' centres cross: each centre is a response-weighted quadratic
   fitted to a band around the line, counting only pixels whose local structure (structure
   tensor of the response) runs along that line, so the line crossing it cannot pull it
   sideways (:class:`LineEvidence`, :func:`refine_crossing`).

The result is a lattice in an arbitrary orientation, matched to the pattern by
:func:`floorscan.calibration.detect.label_lattice`.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import cv2
import numpy as np

from ..errors import CalibrationError
from .lattice import Detection, label_lattice
from .pattern import Pattern

# Lattice directions faced by a cell's four edges, in rotational order.
_DIRS = [(0, -1), (1, 0), (0, 1), (-1, 0)]


@dataclass
class _Cell:
    quad: np.ndarray  # (4, 2) corners, consistently oriented
    label: Optional[Tuple[int, int]] = None
    facing: int = 0  # edge k faces _DIRS[(facing + k) % 4]


class LineEvidence:
    """Where each line's pixels are, for fitting its centre: the response, and the orientation
    of the dark structure around each pixel (the structure tensor of the response's gradient,
    integrated over 1.5 px). Pixels of a line crossing the one being fitted have the other
    orientation and get no weight; inside a wide line, or where two cross, there is no
    gradient and the response alone counts (that part is symmetric about the crossing)."""

    def __init__(self, response: np.ndarray) -> None:
        self.response = response.astype(np.float32)
        gx = cv2.Sobel(self.response, cv2.CV_32F, 1, 0, ksize=3)
        gy = cv2.Sobel(self.response, cv2.CV_32F, 0, 1, ksize=3)
        self.jxx = cv2.GaussianBlur(gx * gx, (0, 0), 1.5)
        self.jxy = cv2.GaussianBlur(gx * gy, (0, 0), 1.5)
        self.jyy = cv2.GaussianBlur(gy * gy, (0, 0), 1.5)
        trace = self.jxx + self.jyy
        peak = cv2.dilate(trace, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (15, 15)))
        self.flat = trace < 0.05 * np.maximum(peak, 1e-12)

    def weights(self, window: Tuple[slice, slice], normal: np.ndarray) -> np.ndarray:
        """Response times how well the local structure has ``normal`` as its across direction
        (1 along the line, 0 on a line crossing it), raveled."""
        nx, ny = float(normal[0]), float(normal[1])
        jxx, jxy, jyy = self.jxx[window], self.jxy[window], self.jyy[window]
        along_normal = (nx * nx * jxx + 2 * nx * ny * jxy + ny * ny * jyy) / np.maximum(
            jxx + jyy, 1e-12
        )
        agree = np.where(self.flat[window], 1.0, np.clip(2.0 * along_normal - 1.0, 0.0, 1.0))
        return (self.response[window] * agree).ravel().astype(np.float64)


@dataclass
class LineResponse:
    """The black-hat response [grey levels] (how much darker a pixel is than the light
    surface around it, for structures narrower than an eighth of the image), its threshold
    for plain floor ``low``, the line pixels, the :class:`LineEvidence` for fitting line
    centres, and the pattern's line width over spacing (the nominal width of a line next to
    the distance between lines, where the band searched around a line starts)."""

    hat: np.ndarray
    low: float
    mask: np.ndarray
    evidence: LineEvidence
    line_fraction: float = 0.1


def line_response(grey: np.ndarray) -> LineResponse:
    """Pixels on dark lines, by hysteresis: connected pixels above a low threshold (a few
    times the response of plain floor) that include one above twice that, so a line blurred
    to low contrast in the distance stays connected to the strong lines it crosses, while
    specks on the floor go."""
    h, w = grey.shape
    k = int(max(15, min(h, w) // 8)) | 1
    img = cv2.GaussianBlur(grey, (0, 0), 0.8)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
    hat = cv2.morphologyEx(img, cv2.MORPH_BLACKHAT, kernel)
    low = max(5.0, 3.0 * float(np.median(hat)))
    weak = (hat >= low).astype(np.uint8)
    n, labels = cv2.connectedComponents(weak, connectivity=8)
    strong = np.zeros(n, bool)
    strong[np.unique(labels[hat >= 2 * low])] = True
    strong[0] = False
    hat = hat.astype(np.float32)
    return LineResponse(hat, low, strong[labels], LineEvidence(hat))


def find_cells(mask: np.ndarray) -> List[_Cell]:
    """Light regions enclosed by lines that are convex quadrilaterals (corners oriented the
    same way round)."""
    h, w = mask.shape
    light = (~mask).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(light, connectivity=4)
    cells = []
    for i in range(1, n):
        x, y, bw, bh, area = stats[i]
        if area < 12 or area > 0.25 * h * w or x == 0 or y == 0 or x + bw >= w or y + bh >= h:
            continue
        comp = (labels[y : y + bh, x : x + bw] == i).astype(np.uint8)
        contours, _ = cv2.findContours(comp, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        c = max(contours, key=len)
        peri = cv2.arcLength(c, True)
        quad = None
        for eps in (0.03, 0.05, 0.08):
            approx = cv2.approxPolyDP(c, eps * peri, True)
            if len(approx) == 4:
                quad = approx.reshape(4, 2).astype(np.float64)
                break
        if quad is None or not cv2.isContourConvex(quad.astype(np.float32)):
            continue
        quad_area = abs(cv2.contourArea(quad.astype(np.float32)))
        if quad_area <= 0 or not 0.75 <= area / quad_area <= 1.3:
            continue
        quad += (x, y)
        # Orient every quad the same way (positive signed area in image coordinates).
        sx = quad[:, 0] * np.roll(quad[:, 1], -1) - np.roll(quad[:, 0], -1) * quad[:, 1]
        if sx.sum() < 0:
            quad = quad[::-1]
        cells.append(_Cell(quad))
    return cells


def _edges(cells: List[_Cell]) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per edge (cell * 4 + k): midpoint, unit direction, length, and the cell's depth behind
    it (the mean length of the two edges beside it) [px]."""
    a = np.stack([c.quad for c in cells])  # (N, 4, 2)
    vec = np.roll(a, -1, axis=1) - a
    mid = a + vec / 2
    length = np.linalg.norm(vec, axis=-1)
    depth = (np.roll(length, 1, axis=1) + np.roll(length, -1, axis=1)) / 2
    unit = vec / np.maximum(length, 1e-9)[..., None]
    return mid.reshape(-1, 2), unit.reshape(-1, 2), length.ravel(), depth.ravel()


def match_edges(cells: List[_Cell]) -> Dict[int, int]:
    """Edge index (cell * 4 + k) -> facing edge of a neighbouring cell, mutual best matches:
    anti-parallel, of similar length, side by side along the edge (offset under a third of
    its length) and closer across it than half the depth of either cell (the line between
    two cells is much thinner than the cells)."""
    mid, unit, length, depth = _edges(cells)
    delta = mid[None] - mid[:, None]  # (E, E, 2)
    along = np.abs(np.sum(delta * unit[:, None], axis=-1))
    across = np.abs(unit[:, None, 0] * delta[..., 1] - unit[:, None, 1] * delta[..., 0])
    cos = unit @ unit.T
    short = np.minimum(length[:, None], length[None])
    ratio = short / np.maximum(length[:, None], length[None])
    same_cell = (np.arange(len(mid))[:, None] // 4) == (np.arange(len(mid))[None] // 4)
    ok = (cos < -0.8) & (ratio > 0.5) & ~same_cell
    ok &= (along < short / 3) & (across < np.maximum(depth[:, None], depth[None]))
    cost = np.where(ok, np.hypot(along, across), np.inf)
    best = np.argmin(cost, axis=1)
    out = {}
    for e, f in enumerate(best):
        if np.isfinite(cost[e, f]) and best[f] == e:
            out[e] = int(f)
    return out


def _walk(
    cells: List[_Cell], matches: Dict[int, int], seed: int, banned: set
) -> Tuple[Dict[int, Tuple[Tuple[int, int], int]], Dict[int, int]]:
    """Breadth-first labelling from ``seed``: cell -> (grid coordinates, facing), and the
    number of contradictions each cell took part in."""
    state = {seed: ((0, 0), 0)}
    conflicts: Dict[int, int] = {}
    queue = deque([seed])
    while queue:
        a = queue.popleft()
        (li, lj), fa = state[a]
        for k in range(4):
            f = matches.get(a * 4 + k)
            if f is None or f // 4 in banned:
                continue
            b, m = divmod(f, 4)
            di, dj = _DIRS[(fa + k) % 4]
            want = ((li + di, lj + dj), (fa + k + 2 - m) % 4)
            if b in state:
                if state[b] != want:
                    conflicts[a] = conflicts.get(a, 0) + 1
                    conflicts[b] = conflicts.get(b, 0) + 1
                continue
            state[b] = want
            queue.append(b)
    seen: Dict[Tuple[int, int], int] = {}
    for c, (label, _f) in state.items():
        if label in seen:
            conflicts[c] = conflicts.get(c, 0) + 1
            conflicts[seen[label]] = conflicts.get(seen[label], 0) + 1
        seen[label] = c
    return state, conflicts


def label_cells(cells: List[_Cell], matches: Dict[int, int]) -> List[_Cell]:
    """Grid coordinates of the largest group of cells connected by matched edges. Cells whose
    neighbours contradict each other (two paths giving different coordinates) are dropped, the
    worst first, until the group is consistent."""
    best: Dict[int, Tuple[Tuple[int, int], int]] = {}
    done: set = set()
    for seed in range(len(cells)):
        if seed in done:
            continue
        banned: set = set()
        start = seed
        while True:
            state, conflicts = _walk(cells, matches, start, banned)
            if not conflicts:
                break
            worst = max(conflicts, key=lambda c: conflicts[c])
            banned.add(worst)
            done.add(worst)
            if worst == start:
                rest = [c for c in state if c not in banned]
                if not rest:
                    state = {}
                    break
                start = rest[0]
        done.update(state)
        if len(state) > len(best):
            best = state
    out = []
    for c, (label, facing) in best.items():
        cells[c].label, cells[c].facing = label, facing
        out.append(cells[c])
    return out


def crossings_of(cells: List[_Cell]) -> Dict[Tuple[int, int], np.ndarray]:
    """Crossing grid coordinates -> mean of the cell corners at it [px]."""
    acc: Dict[Tuple[int, int], List[np.ndarray]] = {}
    for c in cells:
        for k in range(4):
            # Corner k lies between edge k - 1 and edge k.
            faces = {_DIRS[(c.facing + k - 1) % 4], _DIRS[(c.facing + k) % 4]}
            ci = c.label[0] + (1 if (1, 0) in faces else 0)
            cj = c.label[1] + (1 if (0, 1) in faces else 0)
            acc.setdefault((ci, cj), []).append(c.quad[k])
    return {key: np.mean(v, axis=0) for key, v in acc.items()}


def _sample(img: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Bilinear samples of ``img`` at (N, 2) points (u, v); 0 outside."""
    m = pts.astype(np.float32).reshape(-1, 1, 2)
    return cv2.remap(img, m[..., 0], m[..., 1], cv2.INTER_LINEAR, borderValue=0).ravel()


def crossing_strength(hat: np.ndarray, p: np.ndarray, a1: np.ndarray, a2: np.ndarray) -> float:
    """How clearly two lines cross at ``p`` with neighbouring crossings ``p + a1`` and
    ``p + a2`` [px]: the weakest of the four arms' mean line response (each sampled from 0.25
    to 0.4 of the way to the next crossing, clear of the crossing itself and of the overhang
    that ends half a step past the outermost line)."""
    t = np.array([0.25, 0.32, 0.4])
    arms = []
    for a in (a1, -a1, a2, -a2):
        arms.append(float(np.mean(_sample(hat, p[None] + t[:, None] * a[None]))))
    return min(arms)


def _axes_at(
    xs: Dict[Tuple[int, int], np.ndarray], k: Tuple[int, int]
) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """Vectors [px] to the next crossing along each lattice axis at ``k`` (from the neighbour
    on either side), None without neighbours along both axes."""
    axes = []
    for d in ((1, 0), (0, 1)):
        fwd, back = (k[0] + d[0], k[1] + d[1]), (k[0] - d[0], k[1] - d[1])
        if fwd in xs:
            axes.append(xs[fwd] - xs[k])
        elif back in xs:
            axes.append(xs[k] - xs[back])
        else:
            return None
    return axes[0], axes[1]


def refine_crossing(
    response: LineResponse, p: np.ndarray, a1: np.ndarray, a2: np.ndarray
) -> Optional[np.ndarray]:
    """Where the centre lines of the two lines through ``p`` (next crossings at ``p + a1``
    and ``p + a2``) cross [px]. Each centre is a quadratic fitted, weighted by the line's own
    evidence (:class:`LineEvidence`), to a band around the line out to about the next
    crossings; the band starts at the nominal line width plus blur and follows the width
    measured (perspective widens near lines), never past 45% of the distance to the parallel
    line. None if a line is not seen on both sides or the point runs away."""
    dirs = [a1 / np.linalg.norm(a1), a2 / np.linalg.norm(a2)]
    lengths = [float(np.linalg.norm(a1)), float(np.linalg.norm(a2))]
    if min(lengths) < 3:
        return None
    sin_c = max(abs(float(dirs[0][0] * dirs[1][1] - dirs[0][1] * dirs[1][0])), 0.2)
    gap = [lengths[1 - k] * sin_c for k in (0, 1)]
    half = [min(0.75 * response.line_fraction * gap[k] + 1.5, 0.45 * gap[k]) for k in (0, 1)]
    limit = [min(0.45 * gap[k], 2.0 * half[k] + 2.0) for k in (0, 1)]
    reach = [max(1.2 * lengths[k], 8.0) for k in (0, 1)]
    radius = max(reach[k] + limit[k] for k in (0, 1))
    h, w = response.hat.shape
    x0, x1 = int(max(0, np.floor(p[0] - radius))), int(min(w - 1, np.ceil(p[0] + radius)))
    y0, y1 = int(max(0, np.floor(p[1] - radius))), int(min(h - 1, np.ceil(p[1] + radius)))
    if x1 <= x0 or y1 <= y0:
        return None
    window = (slice(y0, y1 + 1), slice(x0, x1 + 1))
    ys, xs = np.mgrid[window]
    pix = np.stack([xs.ravel(), ys.ravel()], axis=-1).astype(np.float64)
    normals = [np.array([-d[1], d[0]]) for d in dirs]
    weights = []
    for n in normals:
        wk = response.evidence.weights(window, n)
        weights.append(np.clip(wk - 0.1 * wk.max(), 0.0, None))
    keep = (weights[0] > 0) | (weights[1] > 0)  # the light floor weighs nothing
    pix = pix[keep]
    weights = [wk[keep] for wk in weights]
    start = np.asarray(p, dtype=np.float64)
    q = start.copy()
    for _ in range(5):
        curves, widths = [], []
        for k, d in enumerate(dirs):
            rel = pix - q
            t, s = rel @ d, rel @ normals[k]
            near = np.abs(t) < reach[k]
            coef = np.zeros(1)
            for _pass in range(2):
                sel = near & (np.abs(s - np.polyval(coef, t)) < half[k])
                wt = weights[k][sel]
                tt = t[sel]
                if np.count_nonzero(wt[tt < 0]) < 2 or np.count_nonzero(wt[tt > 0]) < 2:
                    return None
                deg = 2 if np.ptp(tt) > 4 * half[k] else 1
                coef = np.polyfit(tt, s[sel], deg, w=np.sqrt(wt))
            # Width: spread of the pixels above half the line's peak (a box of width W has
            # variance W^2 / 12; floor texture stays below half the peak).
            core = wt > 0.5 * wt.max()
            off = s[sel][core] - np.polyval(coef, tt[core])
            widths.append(np.sqrt(12.0 * float(np.mean(off**2))) + 1.0)
            curves.append(coef)
        new = _intersect(q, dirs, normals, curves)
        if new is None or np.linalg.norm(new - start) > 0.3 * min(lengths):
            return None
        new_half = [float(np.clip(0.65 * widths[k] + 1.5, 1.5, limit[k])) for k in (0, 1)]
        done = (
            np.linalg.norm(new - q) < 1e-3
            and max(abs(a - b) for a, b in zip(new_half, half)) < 0.25
        )
        q, half = new, new_half
        if done:
            break
    return q


def _intersect(
    p: np.ndarray, dirs: List[np.ndarray], normals: List[np.ndarray], curves: List[np.ndarray]
) -> Optional[np.ndarray]:
    """The point q with ``n_k . (q - p) = curve_k(d_k . (q - p))`` for both lines (Newton)."""
    q = p.copy()
    for _ in range(20):
        f, jac = np.zeros(2), np.zeros((2, 2))
        for k in (0, 1):
            rel = q - p
            t = rel @ dirs[k]
            f[k] = rel @ normals[k] - np.polyval(curves[k], t)
            jac[k] = normals[k] - np.polyval(np.polyder(curves[k]), t) * dirs[k]
        try:
            step = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            return None
        q = q + step
        if not np.all(np.isfinite(q)):
            return None
        if np.linalg.norm(step) < 1e-6:
            break
    return q


def _refine_all(
    response: LineResponse, xs: Dict[Tuple[int, int], np.ndarray], need: float
) -> Dict[Tuple[int, int], np.ndarray]:
    """Every crossing refined and kept if two lines clearly cross there."""
    out = {}
    for k, p in xs.items():
        axes = _axes_at(xs, k)
        if axes is None:
            continue
        q = refine_crossing(response, p, *axes)
        if q is not None and crossing_strength(response.hat, q, *axes) >= need:
            out[k] = q
    return out


def grow_lattice(
    response: LineResponse,
    xs: Dict[Tuple[int, int], np.ndarray],
    limits: Tuple[int, int],
) -> Dict[Tuple[int, int], np.ndarray]:
    """Refines the known crossings and adds the ones next to them where the lattice,
    extrapolated (quadratically when it can, for the perspective), predicts one and two
    lines are found crossing there (the far rows of a pattern, whose cells are too thin to be
    found as cells). The lattice does not grow past ``limits`` (columns, rows)."""
    hat = response.hat
    h, w = hat.shape
    strengths = [
        crossing_strength(hat, xs[k], *axes) for k in xs if (axes := _axes_at(xs, k)) is not None
    ]
    need = max(response.low, 0.2 * float(np.median(strengths))) if strengths else 2 * response.low
    xs = _refine_all(response, xs, need)
    if not xs:
        return xs
    changed = True
    while changed:
        changed = False
        keys = np.array(list(xs))
        lo, hi = keys.min(axis=0), keys.max(axis=0)
        for i, j in list(xs):
            for d in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                new = (i + d[0], j + d[1])
                back = (i - d[0], j - d[1])
                if new in xs or back not in xs:
                    continue
                span = np.maximum(hi, new) - np.minimum(lo, new) + 1
                if span[0] > limits[0] or span[1] > limits[1]:
                    continue
                q, qb = xs[(i, j)], xs[back]
                back2 = (i - 2 * d[0], j - 2 * d[1])
                p = 3 * q - 3 * qb + xs[back2] if back2 in xs else 2 * q - qb
                if not (2 <= p[0] < w - 2 and 2 <= p[1] < h - 2):
                    continue
                side = next(
                    (
                        xs[s] - q if s[0] + s[1] > i + j else q - xs[s]
                        for s in ((i + d[1], j + d[0]), (i - d[1], j - d[0]))
                        if s in xs
                    ),
                    None,
                )
                if side is None:
                    continue
                along = p - q
                r = refine_crossing(response, p, along, side)
                if r is not None and crossing_strength(hat, r, along, side) >= need:
                    xs[new] = r
                    lo, hi = np.minimum(lo, new), np.maximum(hi, new)
                    changed = True
    return xs


MIN_ROWS = 3
"""Fewest rows of crossings (counted away from the camera) accepted when far rows are lost."""


def find_line_crossings(grey: np.ndarray, pattern: Pattern) -> Detection:
    """Finds the crossings of the pattern's line grid and matches them to the pattern. The
    farthest rows may be missing (lines too fine to resolve in the distance) if every line
    running away was found, at least ``MIN_ROWS`` rows were, and the nearest row found is
    the pattern's nearest: one step nearer, inside the image, no line crosses."""
    response = line_response(grey)
    response.line_fraction = pattern.line_width_m / pattern.step_m
    found = find_cells(response.mask)
    cells = label_cells(found, match_edges(found)) if found else []
    expected = pattern.counts
    if not cells:
        raise CalibrationError(_not_found(0, expected, "no cells enclosed by lines"))
    xs = crossings_of(cells)
    keys = np.array(list(xs))
    shape = keys.max(axis=0) - keys.min(axis=0) + 1  # (cols, rows)
    # Grow towards the pattern's size, in the orientation that the core fits.
    if shape[0] <= expected[0] and shape[1] <= expected[1]:
        limits = (
            expected if (shape[0] > expected[1] or shape[1] > expected[0]) else (max(expected),) * 2
        )
    else:
        limits = (expected[1], expected[0])
    xs = grow_lattice(response, xs, limits)
    if not xs:
        raise CalibrationError(_not_found(0, expected, "no line crossings confirmed"))
    keys = np.array(list(xs))
    lo = keys.min(axis=0)
    shape = keys.max(axis=0) - lo + 1
    lattice = np.full((shape[1], shape[0], 2), np.nan)
    for (ci, cj), p in xs.items():
        lattice[cj - lo[1], ci - lo[0]] = p
    method = "line grid (cells, line centres)"
    if sorted(shape.tolist()) == sorted(expected):
        return label_lattice(lattice, pattern, method)
    detail = f"the lines found form a grid of {shape[0]} x {shape[1]} crossings"
    if expected[0] not in shape.tolist() or min(shape) < MIN_ROWS and max(shape) == expected[0]:
        raise CalibrationError(_not_found(len(xs), expected, detail))
    try:
        det = label_lattice(lattice, pattern, method, partial_away=True)
    except CalibrationError:
        raise CalibrationError(_not_found(len(xs), expected, detail)) from None
    rows = int(det.indices[:, 1].max()) + 1
    if rows < MIN_ROWS or not _nearest_row_is_first(response, det):
        raise CalibrationError(
            _not_found(
                len(xs),
                expected,
                detail + ", and the nearest row cannot be told apart from a missing one",
            )
        )
    return Detection(
        det.image_points,
        det.ground_points,
        det.indices,
        f"{method}; {rows} of {expected[1]} rows (the farthest too fine to resolve)",
    )


def _nearest_row_is_first(response: LineResponse, det: Detection) -> bool:
    """True if, one step nearer than the nearest row found, most predicted crossings are
    inside the image and none of them shows two lines crossing."""
    pts = {tuple(k): p for k, p in zip(det.indices.tolist(), det.image_points)}
    h, w = response.hat.shape
    inside = crossing = total = 0
    for (i, j), p0 in pts.items():
        if j != 0 or (i, 1) not in pts:
            continue
        total += 1
        p1 = pts[(i, 1)]
        q = 3 * p0 - 3 * p1 + pts[(i, 2)] if (i, 2) in pts else 2 * p0 - p1
        side = next((pts[s] - p0 for s in ((i + 1, 0), (i - 1, 0)) if s in pts), None)
        if side is None or not (3 <= q[0] < w - 3 and 3 <= q[1] < h - 3):
            continue
        inside += 1
        if crossing_strength(response.hat, q, p0 - q, side) >= 2 * response.low:
            crossing += 1
    return total > 0 and inside >= max(2, (total + 1) // 2) and crossing == 0


def _not_found(found: int, expected: Tuple[int, int], detail: str) -> str:
    return (
        f"grid of {expected[0]} x {expected[1]} lines not found ({detail}; {found} of "
        f"{expected[0] * expected[1]} crossings): check `lines` in the pattern file, that every "
        f"line is in the image and darker than the floor around it, and that the image is in "
        f"focus and evenly lit"
    )
