"""The image-to-floor model fitted by calibration: a central camera with radially symmetric
distortion of unknown form, looking at a plane. No pinhole assumption: fisheye rays beyond 90
degrees from the axis are represented too.

A pixel (u, v) becomes, about the distortion centre (cu, cv) and in units of ``scale_px``,
``x = (u - cu) / s``, ``y = (v - cv) / s``, ``rho^2 = x^2 + y^2``, and the ray direction

    d = (x, y, 1 + k1 rho^2 + k2 rho^4 + k3 rho^6)

(Scaramuzza's omnidirectional model with even terms, which holds the division model and, to
good accuracy, equidistant and Kannala-Brandt fisheyes). The floor point is the homogeneous
``g = H d``: ground (x, y) = (g0 / g2, g1 / g2) [m], camera ground frame; ``g2 <= 0`` means the
ray misses the floor (at or above the horizon).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple

import numpy as np


@dataclass(frozen=True)
class RadialPlaneModel:
    """Image -> floor mapping (see the module docstring).

    - ``centre_px``: (cu, cv) distortion centre [px].
    - ``scale_px``: normalising length [px] (half the larger image side).
    - ``k``: radial coefficients (k1, k2, ...) of the ray's axial component.
    - ``h``: (3, 3) homography from ray directions to homogeneous floor points [m], unit
      Frobenius norm, signed so that the floor is at ``g2 > 0``.
    """

    centre_px: Tuple[float, float]
    scale_px: float
    k: Tuple[float, ...]
    h: np.ndarray

    # --- evaluation ---------------------------------------------------------------------
    def normalised(self, u, v) -> Tuple[np.ndarray, np.ndarray]:
        s = self.scale_px
        return (np.asarray(u, float) - self.centre_px[0]) / s, (
            np.asarray(v, float) - self.centre_px[1]
        ) / s

    def axial(self, rho2: np.ndarray) -> np.ndarray:
        """The ray's axial component 1 + k1 rho^2 + k2 rho^4 + ..."""
        out = np.ones_like(rho2)
        p = np.ones_like(rho2)
        for k in self.k:
            p = p * rho2
            out = out + k * p
        return out

    def homogeneous(self, u, v) -> np.ndarray:
        """g = H d for pixels (u, v): array of shape (3,) + broadcast shape."""
        x, y = self.normalised(u, v)
        x, y = np.broadcast_arrays(x, y)
        z = self.axial(x * x + y * y)
        d = np.stack([x, y, z])
        return np.tensordot(self.h, d, axes=1)

    def ground(self, u, v) -> Tuple[np.ndarray, np.ndarray]:
        """Floor point (x, y) [m] seen at pixel(s) (u, v); NaN where the ray misses the floor."""
        g = self.homogeneous(u, v)
        w = g[2]
        ok = w > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            x = np.where(ok, g[0] / np.where(ok, w, 1.0), np.nan)
            y = np.where(ok, g[1] / np.where(ok, w, 1.0), np.nan)
        return x, y

    def jacobian(self, u, v, h_px: float = 0.5) -> np.ndarray:
        """d(ground)/d(u, v) [m/px] by central differences: (..., 2, 2), rows x, y."""
        u = np.asarray(u, float)
        v = np.asarray(v, float)
        xu1, yu1 = self.ground(u + h_px, v)
        xu0, yu0 = self.ground(u - h_px, v)
        xv1, yv1 = self.ground(u, v + h_px)
        xv0, yv0 = self.ground(u, v - h_px)
        j = np.empty(np.broadcast(u, v).shape + (2, 2))
        j[..., 0, 0] = (xu1 - xu0) / (2 * h_px)
        j[..., 1, 0] = (yu1 - yu0) / (2 * h_px)
        j[..., 0, 1] = (xv1 - xv0) / (2 * h_px)
        j[..., 1, 1] = (yv1 - yv0) / (2 * h_px)
        return j

    def monotonic_radius_px(self, max_radius_px: float) -> float:
        """Largest image radius [px] from the centre up to which the ray's angle from the axis
        keeps growing with the radius (beyond it the fitted polynomial folds back and means
        nothing); ``max_radius_px`` if it never stops within it."""
        s = self.scale_px
        rho = np.linspace(0.0, max_radius_px / s, 2048)[1:]
        z = self.axial(rho * rho)
        theta = np.arctan2(rho, z)
        bad = np.nonzero(np.diff(theta) <= 0)[0]
        return float(max_radius_px if bad.size == 0 else rho[bad[0]] * s)

    # --- description --------------------------------------------------------------------
    def to_dict(self) -> Dict[str, Any]:
        return {
            "model": "central_radial_plane",
            "centre_px": [float(c) for c in self.centre_px],
            "scale_px": float(self.scale_px),
            "k": [float(k) for k in self.k],
            "h": [[float(x) for x in row] for row in self.h],
        }

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> RadialPlaneModel:
        return cls(
            tuple(d["centre_px"]), float(d["scale_px"]), tuple(d["k"]), np.array(d["h"], float)
        )


def normalise_h(h: np.ndarray, sign_from: Optional[np.ndarray] = None) -> np.ndarray:
    """Unit Frobenius norm; sign flipped so that ``(h @ sign_from)[2]`` is mostly positive."""
    h = h / np.linalg.norm(h)
    if sign_from is not None and np.median((h @ sign_from)[2]) < 0:
        h = -h
    return h
