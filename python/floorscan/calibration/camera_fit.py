"""Fitting a :class:`CameraModel` to pattern points: pixels ``uv`` (M, 2) seen at floor points
``ground`` (M, 2) [m], by Levenberg-Marquardt on the reprojection error with priors, and the
covariance of the fitted parameters.

The priors keep one view of a small pattern well posed: square pixels (``fy / fx`` within 2 %),
the principal point near the image centre (4 % of the larger side), each distortion term near
zero at its family's scale (:mod:`.lens_family`). With known intrinsics only the pose is free.
Residuals are in pixels divided by the corner noise, estimated from the fit itself (at least
``MIN_NOISE_PX``), so the covariance is in the data's own units.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import cv2
import numpy as np

from ..errors import CalibrationError
from .camera_model import POSE_SIZE, CameraModel
from .least_squares import levenberg_marquardt
from .lens_family import LensFamily

ASPECT_PRIOR = 0.02
"""Standard deviation of fy / fx about 1."""
CENTRE_PRIOR = 0.04
"""Standard deviation of the principal point about the image centre [fraction of the larger
image side]."""
MIN_NOISE_PX = 0.05
"""Floor of the corner noise the covariance assumes [px]."""
START_NOISE_PX = 0.2
"""Corner noise assumed for the first solve [px]."""


@dataclass
class CameraFit:
    """A fitted model, which parameters were free, and what the fit knows about them.

    - ``free``: (P,) bool over :meth:`CameraModel.vector`.
    - ``covariance``: (F, F) covariance of the free parameters (F = free.sum()).
    - ``residual_px``: (M, 2) reprojection residuals [px]; ``noise_px``: estimated corner noise.
    """

    model: CameraModel
    free: np.ndarray
    covariance: np.ndarray
    residual_px: np.ndarray
    noise_px: float

    @property
    def rms_px(self) -> float:
        return float(np.sqrt(np.mean(np.sum(self.residual_px**2, axis=1))))


def _prior(family: LensFamily, image_size: Tuple[int, int]):
    """Prior residual function r(p) / (mean, sd) over the lens parameters."""
    w, h = image_size
    side = max(w, h)
    centre = ((w - 1) / 2.0, (h - 1) / 2.0)
    terms = np.array([m for m, _ in family.prior], float)
    sds = np.array([s for _, s in family.prior], float)

    def residual(lens: np.ndarray) -> np.ndarray:
        fx, fy, cx, cy = lens[:4]
        out = [
            (fy / fx - 1.0) / ASPECT_PRIOR,
            (cx - centre[0]) / (CENTRE_PRIOR * side),
            (cy - centre[1]) / (CENTRE_PRIOR * side),
        ]
        return np.concatenate([out, (lens[4:] - terms) / sds])

    return residual


def _numeric_jacobian(fun_batch, p: np.ndarray, free_idx: np.ndarray) -> np.ndarray:
    """Central differences of ``fun_batch`` ((K, P) parameter vectors -> (K, R) residuals)
    with respect to the parameters ``free_idx``, all perturbations in one call."""
    h = 1e-6 * np.maximum(np.abs(p[free_idx]), 1.0)
    batch = np.repeat(p[None], 2 * free_idx.size, axis=0)
    rows = np.arange(free_idx.size)
    batch[2 * rows, free_idx] += h
    batch[2 * rows + 1, free_idx] -= h
    r = fun_batch(batch)
    return ((r[0::2] - r[1::2]) / (2 * h)[:, None]).T


def _solve(
    start: CameraModel,
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    free: np.ndarray,
    noise_px: float,
    max_iterations: int,
) -> Tuple[CameraModel, np.ndarray, np.ndarray]:
    """One LM solve; returns (model, residual vector function at optimum's Jacobian, data
    residuals (M, 2) [px])."""
    prior = _prior(start.family, image_size)
    n_lens = start.family.size
    lens_free = bool(free[:n_lens].any())
    full0 = start.vector()
    free_idx = np.nonzero(free)[0]

    def full_of(q: np.ndarray) -> np.ndarray:
        p = full0.copy()
        p[free_idx] = q
        return p

    def res_batch(ps: np.ndarray) -> np.ndarray:
        u, v = start.project_ground_batch(ps, ground[:, 0], ground[:, 1])  # (K, M)
        e = np.stack([u - uv[:, 0], v - uv[:, 1]], axis=-1).reshape(len(ps), -1)
        e = np.where(np.isfinite(e), e, 1e4) / noise_px
        if not lens_free:
            return e
        return np.hstack([e, np.stack([prior(p[:n_lens]) for p in ps])])

    def fun(q: np.ndarray):
        p = full_of(q)
        r = res_batch(p[None])[0]
        return r, _numeric_jacobian(res_batch, p, free_idx)

    q, jac = levenberg_marquardt(fun, full0[free_idx], max_iterations=max_iterations)
    model = start.with_vector(full_of(q))
    u, v = model.project_ground(ground[:, 0], ground[:, 1])
    return model, jac, np.column_stack([u, v]) - uv


def refine(
    start: CameraModel,
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    *,
    fix_lens: bool = False,
    max_iterations: int = 60,
    noise_px: Optional[float] = None,
) -> CameraFit:
    """Refines ``start`` on the points; the lens is held fixed with ``fix_lens``. The corner
    noise is estimated from the first solve's residuals (or given as ``noise_px``) and the
    second solve weighs the priors against it."""
    n_lens = start.family.size
    free = np.ones(n_lens + POSE_SIZE, bool)
    if fix_lens:
        free[:n_lens] = False
    n_free = int(free.sum())
    dof = max(2 * len(uv) - n_free, 1)
    model, jac, res = _solve(
        start, uv, ground, image_size, free, noise_px or START_NOISE_PX, max_iterations
    )
    sigma = noise_px
    if sigma is None:
        finite = np.all(np.isfinite(res), axis=1)
        sigma = max(float(np.sqrt(np.sum(res[finite] ** 2) / dof)), MIN_NOISE_PX)
        model, jac, res = _solve(model, uv, ground, image_size, free, sigma, max_iterations)
        finite = np.all(np.isfinite(res), axis=1)
        sigma = max(float(np.sqrt(np.sum(res[finite] ** 2) / dof)), MIN_NOISE_PX)
        # The Jacobian's data rows were whitened with the solve's noise; covariance with the
        # final estimate (priors unchanged).
    a = jac.T @ jac
    try:
        cov = np.linalg.inv(a + 1e-12 * np.trace(a) / a.shape[0] * np.eye(a.shape[0]))
    except np.linalg.LinAlgError:
        cov = np.full_like(a, np.inf)
    return CameraFit(model, free, cov, res, sigma)


def initial_models(
    family: LensFamily,
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    *,
    lens: Optional[np.ndarray] = None,
    candidates: int = 2,
) -> Sequence[CameraModel]:
    """Starting points: for focal lengths over a wide range (or the given ``lens``), the
    pixels' rays through the family with its prior distortion, a planar PnP (IPPE) for the
    pose; the ``candidates`` with the least reprojection error."""
    w, h = image_size
    side = max(w, h)
    if lens is not None:
        lenses = [np.asarray(lens, float)]
    else:
        terms = family.default_terms()
        lenses = [
            np.concatenate([[f, f, (w - 1) / 2.0, (h - 1) / 2.0], terms])
            for f in side * np.geomspace(0.15, 3.0, 24)
        ]
    object_points = np.column_stack([ground, np.zeros(len(ground))]).astype(np.float64)
    scored = []
    for lp in lenses:
        ray = family.unproject(lp, uv[:, 0], uv[:, 1])
        ok = np.all(np.isfinite(ray), axis=0) & (ray[2] > 0.05)
        if ok.sum() < 6:
            continue
        img = (ray[:2, ok] / ray[2, ok]).T.astype(np.float64)
        try:
            good, rvec, tvec = cv2.solvePnP(
                object_points[ok], img, np.eye(3), None, flags=cv2.SOLVEPNP_IPPE
            )
        except cv2.error:
            continue
        if not good:
            continue
        r, _ = cv2.Rodrigues(rvec)
        centre = (-r.T @ tvec).ravel()
        if centre[2] <= 0:
            continue
        m = CameraModel(family, lp, rvec.ravel(), centre)
        u, v = m.project_ground(ground[:, 0], ground[:, 1])
        e = np.hypot(u - uv[:, 0], v - uv[:, 1])
        cost = float(np.sqrt(np.mean(np.where(np.isfinite(e), e, 1e4) ** 2)))
        scored.append((cost, m))
    if not scored:
        raise CalibrationError(
            f"the {family.name} lens model found no camera pose above the floor for the "
            "pattern's points (a mirrored pattern, or points that do not lie on the floor)"
        )
    scored.sort(key=lambda s: s[0])
    return [m for _, m in scored[:candidates]]


def fit_family(
    family: LensFamily,
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    *,
    lens: Optional[np.ndarray] = None,
) -> CameraFit:
    """The best fit of one family from its starting points (pose only when ``lens`` is
    given)."""
    best: Optional[CameraFit] = None
    for start in initial_models(family, uv, ground, image_size, lens=lens):
        fit = refine(start, uv, ground, image_size, fix_lens=lens is not None)
        if best is None or fit.rms_px < best.rms_px:
            best = fit
    assert best is not None
    return best
