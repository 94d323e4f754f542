"""The physical model a calibration fits: a central camera (a :class:`LensFamily` with its
intrinsics) at a pose above the floor plane. Unlike a free image-to-floor mapping it
extrapolates: beyond the pattern the floor point still follows from the lens and the pose.

Frames: the camera ground frame (origin on the floor below the camera, x forward, y left, z up,
metres) in which the pattern is described; the optical frame (x right, y down, z along the
axis). ``camera_from_ground`` is the rotation (a Rodrigues vector) taking ground-frame
directions into the optical frame; ``centre_m`` is the camera's optical centre in the ground
frame (z is its height above the floor).

>>> import numpy as np
>>> from floorscan.calibration.lens_family import FAMILIES
>>> m = CameraModel.looking_down(FAMILIES["pinhole_k1"], np.array([300., 300., 319.5, 239.5, 0.]),
...                              height_m=0.3, tilt_rad=0.5)
>>> x, y = m.ground(319.5, 239.5)          # the optical axis meets the floor at h / tan(tilt)
>>> bool(abs(x - 0.3 / np.tan(0.5)) < 1e-9 and abs(y) < 1e-9)
True
>>> u, v = m.project_ground(np.array([x]), np.array([y]))
>>> bool(abs(u[0] - 319.5) < 1e-6 and abs(v[0] - 239.5) < 1e-6)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Tuple

import cv2
import numpy as np

from .lens_family import FAMILIES, LensFamily

POSE_SIZE = 6
"""Rodrigues vector (3) and optical centre [m] (3)."""


def rotation(rvec: np.ndarray) -> np.ndarray:
    """3 x 3 rotation matrix of a Rodrigues vector."""
    r, _ = cv2.Rodrigues(np.asarray(rvec, np.float64).reshape(3, 1))
    return r


@dataclass(frozen=True)
class CameraModel:
    """A lens family with intrinsics ``lens_params`` (fx, fy, cx, cy, terms...) and a pose:
    ``camera_from_ground`` (Rodrigues vector) and ``centre_m`` (x, y, z) [m]."""

    family: LensFamily
    lens_params: np.ndarray
    camera_from_ground: np.ndarray
    centre_m: np.ndarray

    @classmethod
    def looking_down(
        cls, family: LensFamily, lens_params: np.ndarray, *, height_m: float, tilt_rad: float
    ) -> CameraModel:
        """A camera ``height_m`` [m] above the ground origin looking along +x, tilted down by
        ``tilt_rad`` [rad] (for tests and starting points)."""
        # Optical axis (0, 0, 1) -> ground (cos t, 0, -sin t); optical x (right) -> ground -y;
        # optical y (down) -> ground (-sin t, 0, -cos t).
        c, s = np.cos(tilt_rad), np.sin(tilt_rad)
        ground_from_camera = np.array([[0.0, -s, c], [-1.0, 0.0, 0.0], [0.0, -c, -s]])
        rvec, _ = cv2.Rodrigues(ground_from_camera.T)
        return cls(family, np.asarray(lens_params, float), rvec.ravel(), np.array([0, 0, height_m]))

    # --- parameter vector ---------------------------------------------------------------
    def vector(self) -> np.ndarray:
        return np.concatenate([self.lens_params, self.camera_from_ground, self.centre_m])

    def with_vector(self, p: np.ndarray) -> CameraModel:
        n = self.family.size
        return CameraModel(self.family, p[:n].copy(), p[n : n + 3].copy(), p[n + 3 : n + 6].copy())

    # --- geometry -----------------------------------------------------------------------
    @property
    def height_m(self) -> float:
        return float(self.centre_m[2])

    def project_ground(self, x, y) -> Tuple[np.ndarray, np.ndarray]:
        """Pixels (u, v) where floor points (x, y) [m] appear; NaN where not imaged."""
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        p = np.stack([x - self.centre_m[0], y - self.centre_m[1], -self.centre_m[2] + 0 * x])
        cam = np.tensordot(rotation(self.camera_from_ground), p, axes=1)
        return self.family.project(self.lens_params, cam)

    def project_ground_batch(self, vectors: np.ndarray, x, y) -> Tuple[np.ndarray, np.ndarray]:
        """:meth:`project_ground` for K parameter vectors (K, P) at once: (K, M) pixels."""
        vectors = np.asarray(vectors, float)
        n = self.family.size
        k = len(vectors)
        rot = np.stack([rotation(r) for r in vectors[:, n : n + 3]])  # (K, 3, 3)
        centre = vectors[:, n + 3 : n + 6]  # (K, 3)
        pts = np.stack([np.asarray(x, float), np.asarray(y, float), np.zeros(np.size(x))])
        rel = pts[None] - centre[:, :, None]  # (K, 3, M)
        cam = np.einsum("kij,kjm->ikm", rot, rel)  # (3, K, M)
        lens = vectors[:, :n].T.reshape(n, k, 1)
        return self.family.project(lens, cam)

    def rays(self, u, v) -> np.ndarray:
        """Unit rays (3, ...) in the ground frame seen at pixels (u, v); NaN where the lens
        model is not valid."""
        ray = self.family.unproject(self.lens_params, u, v)
        return np.tensordot(rotation(self.camera_from_ground).T, ray, axes=1)

    def ground(self, u, v, *, min_depression_rad: float = 0.0) -> Tuple[np.ndarray, np.ndarray]:
        """Floor points (x, y) [m] seen at pixels (u, v); NaN where the ray does not point
        down by more than ``min_depression_rad`` [rad] (at or above the horizon)."""
        r = self.rays(u, v)
        with np.errstate(all="ignore"):
            down = r[2] < -np.sin(min_depression_rad) - 1e-12
            t = np.where(down, -self.centre_m[2] / np.where(down, r[2], -1.0), np.nan)
            return self.centre_m[0] + t * r[0], self.centre_m[1] + t * r[1]

    def jacobian_det(self, u, v, h_px: float = 0.5) -> np.ndarray:
        """Determinant of d(ground)/d(u, v) by central differences (its sign tells whether
        the floor is seen mirrored: a camera above the floor gives a negative one)."""
        xu1, yu1 = self.ground(np.asarray(u) + h_px, v)
        xu0, yu0 = self.ground(np.asarray(u) - h_px, v)
        xv1, yv1 = self.ground(u, np.asarray(v) + h_px)
        xv0, yv0 = self.ground(u, np.asarray(v) - h_px)
        return ((xu1 - xu0) * (yv1 - yv0) - (xv1 - xv0) * (yu1 - yu0)) / (4 * h_px * h_px)

    # --- description --------------------------------------------------------------------
    def to_dict(self) -> Dict[str, Any]:
        ground_from_camera = rotation(self.camera_from_ground).T
        axis = ground_from_camera[:, 2]
        return {
            "model": "central_camera",
            "lens": self.family.to_lens_dict(self.lens_params),
            "camera_from_ground_rodrigues": [float(a) for a in self.camera_from_ground],
            "centre_m": [float(a) for a in self.centre_m],
            "height_m": float(self.centre_m[2]),
            "tilt_rad": float(-np.arcsin(np.clip(axis[2], -1, 1))),
            "heading_rad": float(np.arctan2(axis[1], axis[0])),
        }

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> CameraModel:
        family = FAMILIES[d["lens"]["model"]]
        params = d["lens"]["params"]
        return cls(
            family,
            np.array([params[n] for n in family.parameter_names], float),
            np.array(d["camera_from_ground_rodrigues"], float),
            np.array(d["centre_m"], float),
        )
