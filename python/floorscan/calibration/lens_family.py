"""Lens families a calibration chooses among: the projection from a ray in the camera's optical
frame (x right, y down, z along the axis) to a pixel, and back, for a parameter vector.

Every family's parameters start with ``fx, fy, cx, cy`` [px]; the distortion terms follow:

- ``pinhole``: OpenCV's plumb_bob, ``k1, k2, p1, p2, k3`` (any leading subset is a member:
  ``pinhole_k1``, ``pinhole_k2``, ``pinhole_k2p``, ``pinhole_k3``). Rays up to about 80 degrees
  from the axis.
- ``kannala_brandt``: OpenCV's fisheye, ``theta_d = theta (1 + k1 theta^2 + ... + k4 theta^8)``
  (``equidistant`` has no terms; ``kb1``, ``kb2``, ``kb4``). Rays beyond 90 degrees too.
- ``unified``: Mei's unified model (a pinhole behind a unit sphere), ``xi`` and optionally
  ``k1, k2`` on the sphere-projected point (``ucm``, ``mei_k2``).
- ``division``: Fitzgibbon's one-parameter division model, ray ``(x, y, 1 + lambda r^2)``.

Each family states a prior (mean, standard deviation) per distortion term: weak enough that
data overrules it, firm enough that one view of a small pattern does not let a term wander where
there is no data (the extrapolation problem). Units of the terms are OpenCV's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Tuple

import numpy as np

INTRINSIC_NAMES = ("fx", "fy", "cx", "cy")


@dataclass(frozen=True)
class LensFamily:
    """One member of a lens family: ``kind`` (``pinhole``, ``kannala_brandt``, ``unified``,
    ``division``), its distortion term names, and their priors (mean, sd)."""

    name: str
    kind: str
    terms: Tuple[str, ...]
    prior: Tuple[Tuple[float, float], ...]

    @property
    def parameter_names(self) -> Tuple[str, ...]:
        return INTRINSIC_NAMES + self.terms

    @property
    def size(self) -> int:
        return 4 + len(self.terms)

    def params_dict(self, p: np.ndarray) -> Dict[str, float]:
        return {n: float(x) for n, x in zip(self.parameter_names, p)}

    def default_terms(self) -> np.ndarray:
        return np.array([m for m, _ in self.prior], float)

    # --- projection --------------------------------------------------------------------
    def project(self, p: np.ndarray, ray: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Pixels (u, v) of rays ``ray`` (3, ...) in the optical frame; NaN where the family
        cannot image the ray. ``p`` may also be a batch (size, K, 1) of parameter vectors
        with ``ray`` (3, K, M): one projection per vector (numeric derivatives)."""
        fx, fy, cx, cy = p[:4]
        t = dict(zip(self.terms, p[4:]))
        x, y, z = ray[0], ray[1], ray[2]
        with np.errstate(all="ignore"):
            if self.kind == "pinhole":
                ok = z > 1e-9
                xn = np.where(ok, x / np.where(ok, z, 1.0), np.nan)
                yn = np.where(ok, y / np.where(ok, z, 1.0), np.nan)
                # Past the radius where the radial factor folds back, the model means nothing.
                ks = [t.get(k, 0.0) for k in ("k1", "k2", "k3")]
                if np.ndim(fx) == 0:
                    r_max = _radial_monotonic_limit(ks)
                else:
                    kb = np.broadcast_arrays(*[np.asarray(k, float) for k in ks])
                    r_max = np.array(
                        [_radial_monotonic_limit([k[i, 0] for k in kb]) for i in range(len(kb[0]))]
                    )[:, None]
                inside = np.hypot(xn, yn) < r_max
                xn, yn = np.where(inside, xn, np.nan), np.where(inside, yn, np.nan)
                xd, yd = _plumb_bob(xn, yn, t)
            elif self.kind == "kannala_brandt":
                r = np.hypot(x, y)
                theta = np.arctan2(r, z)
                theta_d = theta * _poly(theta * theta, [t.get(f"k{i}", 0.0) for i in (1, 2, 3, 4)])
                scale = np.where(r > 1e-15, theta_d / np.where(r > 1e-15, r, 1.0), 1.0 / z)
                xd, yd = x * scale, y * scale
            elif self.kind == "unified":
                xi = t["xi"]
                d = np.sqrt(x * x + y * y + z * z)
                den = z + xi * d
                ok = den > 1e-9
                xs = np.where(ok, x / np.where(ok, den, 1.0), np.nan)
                ys = np.where(ok, y / np.where(ok, den, 1.0), np.nan)
                r2 = xs * xs + ys * ys
                radial = 1 + t.get("k1", 0.0) * r2 + t.get("k2", 0.0) * r2 * r2
                xd, yd = xs * radial, ys * radial
            elif self.kind == "division":
                lam = t["lambda"]
                ok = z > 1e-9
                tu = np.where(ok, np.hypot(x, y) / np.where(ok, z, 1.0), np.nan)
                disc = 1 - 4 * lam * tu * tu
                rd = np.where(disc >= 0, 2 * tu / (1 + np.sqrt(np.maximum(disc, 0))), np.nan)
                scale = np.where(tu > 1e-15, rd / np.where(tu > 1e-15, tu, 1.0), 1.0)
                xd = np.where(ok, x / np.where(ok, z, 1.0), np.nan) * scale
                yd = np.where(ok, y / np.where(ok, z, 1.0), np.nan) * scale
            else:  # pragma: no cover - families are built below
                raise ValueError(self.kind)
        return fx * xd + cx, fy * yd + cy

    def unproject(self, p: np.ndarray, u, v) -> np.ndarray:
        """Unit rays (3, ...) in the optical frame seen at pixels (u, v); NaN where the
        projection is not invertible (beyond the radius up to which it is monotonic)."""
        fx, fy, cx, cy = p[:4]
        t = dict(zip(self.terms, p[4:]))
        xd = (np.asarray(u, float) - cx) / fx
        yd = (np.asarray(v, float) - cy) / fy
        with np.errstate(all="ignore"):
            if self.kind == "pinhole":
                x, y, ok = _undistort_plumb_bob(xd, yd, t)
                ray = np.stack([x, y, np.ones_like(x)])
            elif self.kind == "kannala_brandt":
                ks = [t.get(f"k{i}", 0.0) for i in (1, 2, 3, 4)]
                theta_d = np.hypot(xd, yd)
                theta, ok = _invert_kb(theta_d, ks)
                s = np.where(
                    theta_d > 1e-15, np.sin(theta) / np.where(theta_d > 1e-15, theta_d, 1), 1
                )
                ray = np.stack([xd * s, yd * s, np.cos(theta)])
            elif self.kind == "unified":
                xs, ys, ok = _undistort_radial(xd, yd, t.get("k1", 0.0), t.get("k2", 0.0))
                xi = t["xi"]
                r2 = xs * xs + ys * ys
                disc = 1 + (1 - xi * xi) * r2
                ok &= disc >= 0
                fac = (xi + np.sqrt(np.maximum(disc, 0))) / (r2 + 1)
                ray = np.stack([fac * xs, fac * ys, fac - xi])
            elif self.kind == "division":
                lam = t["lambda"]
                r2 = xd * xd + yd * yd
                ray = np.stack([xd, yd, 1 + lam * r2])
                # Monotonic: the angle from the axis grows with r while 1 - lam r^2 > 0.
                ok = 1 - lam * r2 > 0
            else:  # pragma: no cover
                raise ValueError(self.kind)
            n = np.sqrt(np.sum(ray * ray, axis=0))
            ray = ray / n
        return np.where(ok & np.isfinite(n), ray, np.nan)

    def to_lens_dict(self, p: np.ndarray) -> Dict[str, object]:
        """The fitted lens as a dictionary (``model`` and ``params``; the names of
        :class:`floorscan.Lens` where it has the family, and OpenCV's order)."""
        return {"model": self.name, "kind": self.kind, "params": self.params_dict(p)}


def _poly(x2: np.ndarray, ks) -> np.ndarray:
    out = np.ones_like(x2)
    p = np.ones_like(x2)
    for k in ks:
        p = p * x2
        out = out + k * p
    return out


def _plumb_bob(x, y, t):
    r2 = x * x + y * y
    radial = _poly(r2, [t.get("k1", 0.0), t.get("k2", 0.0), t.get("k3", 0.0)])
    p1, p2 = t.get("p1", 0.0), t.get("p2", 0.0)
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return xd, yd


def _radial_monotonic_limit(ks) -> float:
    """Largest undistorted radius up to which r * (1 + k1 r^2 + k2 r^4 + k3 r^6) keeps growing:
    the smallest positive root s = r^2 of its derivative 1 + 3 k1 s + 5 k2 s^2 + 7 k3 s^3
    (1e3 if none)."""
    c = [(2 * n + 1) * float(k) for n, k in enumerate(ks, start=1)]
    while c and c[-1] == 0.0:
        c.pop()
    if not c:
        return 1e3
    if len(c) == 1:
        return float(np.sqrt(-1.0 / c[0])) if c[0] < 0 else 1e3
    if len(c) == 2:
        a, b = c[1], c[0]
        disc = b * b - 4 * a
        if disc < 0:
            return 1e3
        cand = [(-b - np.sqrt(disc)) / (2 * a), (-b + np.sqrt(disc)) / (2 * a)]
        pos = [x for x in cand if x > 0]
        return float(np.sqrt(min(pos))) if pos else 1e3
    roots = np.roots([*reversed(c), 1.0])
    real = roots.real[(np.abs(roots.imag) < 1e-9) & (roots.real > 0)]
    return float(np.sqrt(real.min())) if real.size else 1e3


def _undistort_plumb_bob(xd, yd, t, iterations: int = 30):
    """Undistorted normalised (x, y) of distorted (xd, yd) by Newton's method, and a validity
    mask (converged, inside the radius up to which the radial factor is monotonic)."""
    ks = [t.get("k1", 0.0), t.get("k2", 0.0), t.get("k3", 0.0)]
    p1, p2 = t.get("p1", 0.0), t.get("p2", 0.0)
    r_max = _radial_monotonic_limit(ks)
    # Start from the radial-only inverse along the ray (robust for strong barrel distortion).
    rd = np.hypot(xd, yd)
    ru = _invert_radial(rd, ks, r_max)
    s = np.where(rd > 1e-15, ru / np.where(rd > 1e-15, rd, 1.0), 1.0)
    x, y = xd * s, yd * s
    h = 1e-7
    for _ in range(iterations if (p1 or p2) else 0):
        fx, fy = _plumb_bob(x, y, t)
        ex, ey = fx - xd, fy - yd
        ax, ay = _plumb_bob(x + h, y, t)
        bx, by = _plumb_bob(x, y + h, t)
        j00, j10 = (ax - fx) / h, (ay - fy) / h
        j01, j11 = (bx - fx) / h, (by - fy) / h
        det = j00 * j11 - j01 * j10
        det = np.where(np.abs(det) > 1e-12, det, np.nan)
        x = x - (j11 * ex - j01 * ey) / det
        y = y - (-j10 * ex + j00 * ey) / det
    fx, fy = _plumb_bob(x, y, t)
    ok = np.isfinite(ru) & (np.hypot(x, y) < r_max) & (np.hypot(fx - xd, fy - yd) < 1e-6)
    return x, y, ok


def _invert_radial(rd, ks, r_max, iterations: int = 40):
    """ru with ru (1 + k1 ru^2 + ...) = rd on [0, r_max), by safeguarded Newton; NaN beyond."""
    g_max = r_max * float(_poly(np.array(r_max * r_max), ks)) if r_max < 1e3 else np.inf
    ru = np.array(rd, float, copy=True)
    for _ in range(iterations):
        r2 = ru * ru
        g = ru * _poly(r2, ks) - rd
        dg = 1 + sum((2 * n + 1) * k * r2**n for n, k in enumerate(ks, start=1))
        ru = np.clip(ru - g / np.where(np.abs(dg) > 1e-12, dg, 1e-12), 0, min(r_max, 1e3))
    ok = rd < g_max
    return np.where(ok, ru, np.nan)


def _undistort_radial(xd, yd, k1, k2):
    ks = [k1, k2]
    r_max = _radial_monotonic_limit(ks)
    rd = np.hypot(xd, yd)
    ru = _invert_radial(rd, ks, r_max)
    s = np.where(rd > 1e-15, ru / np.where(rd > 1e-15, rd, 1.0), 1.0)
    return xd * s, yd * s, np.isfinite(ru)


def _invert_kb(theta_d, ks, iterations: int = 40):
    """theta in [0, pi) with theta (1 + k1 theta^2 + ...) = theta_d, while monotonic."""
    th = np.linspace(0, np.pi, 4001)[1:]
    g = th * _poly(th * th, ks)
    bad = np.nonzero(np.diff(g) <= 0)[0]
    th_max = float(th[bad[0]]) if bad.size else np.pi
    g_max = float(th_max * _poly(np.array(th_max * th_max), ks))
    theta = np.array(theta_d, float, copy=True)
    for _ in range(iterations):
        t2 = theta * theta
        e = theta * _poly(t2, ks) - theta_d
        de = 1 + sum((2 * n + 1) * k * t2**n for n, k in enumerate(ks, start=1))
        theta = np.clip(theta - e / np.where(np.abs(de) > 1e-12, de, 1e-12), 0, th_max)
    ok = theta_d < g_max
    return np.where(ok, theta, np.nan), ok


def _family(name, kind, terms, prior) -> LensFamily:
    return LensFamily(name, kind, tuple(terms), tuple(prior))


# Priors: plumb_bob terms as seen on webcams to 120-degree lenses (|k1| < 0.5, |k2| < 0.3,
# tangential < 0.01); Kannala-Brandt terms of fisheyes (|k_i| < 0.1); Mei's xi in [0, 2].
FAMILIES: Dict[str, LensFamily] = {
    f.name: f
    for f in (
        _family("pinhole_k1", "pinhole", ["k1"], [(0.0, 0.5)]),
        _family("pinhole_k2", "pinhole", ["k1", "k2"], [(0.0, 0.5), (0.0, 0.3)]),
        _family(
            "pinhole_k2p",
            "pinhole",
            ["k1", "k2", "p1", "p2"],
            [(0.0, 0.5), (0.0, 0.3), (0.0, 0.01), (0.0, 0.01)],
        ),
        _family("pinhole_k3", "pinhole", ["k1", "k2", "k3"], [(0.0, 0.5), (0.0, 0.3), (0.0, 0.1)]),
        _family("equidistant", "kannala_brandt", [], []),
        _family("kb1", "kannala_brandt", ["k1"], [(0.0, 0.1)]),
        _family("kb2", "kannala_brandt", ["k1", "k2"], [(0.0, 0.1), (0.0, 0.05)]),
        _family(
            "kb4",
            "kannala_brandt",
            ["k1", "k2", "k3", "k4"],
            [(0.0, 0.1), (0.0, 0.05), (0.0, 0.02), (0.0, 0.01)],
        ),
        _family("ucm", "unified", ["xi"], [(0.8, 1.0)]),
        _family("mei_k2", "unified", ["xi", "k1", "k2"], [(0.8, 1.0), (0.0, 0.3), (0.0, 0.2)]),
        _family("division", "division", ["lambda"], [(0.0, 1.0)]),
    )
}
"""Every family member by name."""

DEFAULT_FAMILIES = (
    "pinhole_k1",
    "pinhole_k2",
    "pinhole_k2p",
    "pinhole_k3",
    "equidistant",
    "kb1",
    "kb2",
    "kb4",
    "ucm",
    "mei_k2",
    "division",
)
"""Members tried by default, in order of preference when they predict equally well."""
