"""Fitting the :class:`RadialPlaneModel` to pattern points by nonlinear least squares
(Levenberg-Marquardt, numpy only), choosing the number of distortion terms by leave-one-out error.

Residuals are ground errors mapped back into the image through the model's local Jacobian, so
each point counts by its image error (the detector's noise is in pixels; far points, where a
pixel covers centimetres, do not dominate the fit). A weak prior keeps the distortion centre
near the image centre when the data cannot place it (a nearly pinhole lens).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np

from ..errors import CalibrationError
from .model import RadialPlaneModel, normalise_h

CENTRE_PRIOR = 0.25
"""Standard deviation of the distortion centre's prior [fraction of ``scale_px``]."""
NOISE_PX = 0.1
"""Typical corner noise [px]: the unit the prior's weight is expressed in."""


@dataclass(frozen=True)
class ModelSpec:
    """Which parameters are free: ``terms`` radial coefficients (0..3), ``free_centre``."""

    terms: int
    free_centre: bool

    @property
    def parameter_count(self) -> int:
        return 8 + self.terms + (2 if self.free_centre else 0)


CANDIDATES: Sequence[ModelSpec] = (
    ModelSpec(1, False),
    ModelSpec(2, False),
    ModelSpec(1, True),
    ModelSpec(2, True),
    ModelSpec(3, True),
)
"""Models tried, simplest first."""


@dataclass
class Fit:
    """A fitted model and what the fit knows about it."""

    model: RadialPlaneModel
    spec: ModelSpec
    residual_px: np.ndarray  # (M, 2) image-equivalent residuals [px]
    ground_error_m: np.ndarray  # (M,) distance between model and pattern [m]
    loo_px: np.ndarray  # (M,) linearised leave-one-out error [px]


# --- parameter vector <-> model ---------------------------------------------------------
class _Packing:
    def __init__(self, spec: ModelSpec, centre0: Tuple[float, float], scale: float):
        self.spec, self.centre0, self.scale = spec, centre0, scale

    def pack(self, m: RadialPlaneModel) -> np.ndarray:
        parts: List[float] = []
        if self.spec.free_centre:
            parts += [
                (m.centre_px[0] - self.centre0[0]) / self.scale,
                (m.centre_px[1] - self.centre0[1]) / self.scale,
            ]
        k = list(m.k) + [0.0] * (self.spec.terms - len(m.k))
        parts += k[: self.spec.terms]
        return np.concatenate([np.array(parts, float), m.h.ravel()])

    def unpack(self, p: np.ndarray, fixed_centre: Tuple[float, float]) -> RadialPlaneModel:
        i = 0
        centre = fixed_centre
        if self.spec.free_centre:
            centre = (self.centre0[0] + p[0] * self.scale, self.centre0[1] + p[1] * self.scale)
            i = 2
        k = tuple(p[i : i + self.spec.terms])
        h = p[i + self.spec.terms :].reshape(3, 3)
        return RadialPlaneModel(centre, self.scale, k, h)


def _residuals(
    model: RadialPlaneModel, uv: np.ndarray, ground: np.ndarray
) -> Tuple[np.ndarray, np.ndarray]:
    """(M, 2) image-equivalent residuals [px] and (M,) ground errors [m]; huge where a point
    falls off the floor or the mapping is singular."""
    x, y = model.ground(uv[:, 0], uv[:, 1])
    e = np.column_stack([x, y]) - ground
    jac = model.jacobian(uv[:, 0], uv[:, 1])
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    good = np.all(np.isfinite(e), axis=1) & np.isfinite(det) & (np.abs(det) > 1e-18)
    r = np.full_like(e, 1e6)
    if np.any(good):
        r[good] = np.linalg.solve(jac[good], e[good][..., None])[..., 0]
    return r, np.where(good, np.hypot(e[:, 0], e[:, 1]), np.inf)


def levenberg_marquardt(
    fun: Callable[[np.ndarray], np.ndarray],
    p0: np.ndarray,
    *,
    max_iterations: int = 100,
    step: float = 1e-6,
    tolerance: float = 1e-12,
) -> Tuple[np.ndarray, np.ndarray]:
    """Minimises ``sum(fun(p)^2)`` from ``p0``; returns (p, Jacobian at p). Forward-difference
    Jacobian, Marquardt's diagonal scaling."""
    p = np.asarray(p0, float).copy()
    r = fun(p)
    cost = float(r @ r)
    lam = 1e-3

    def jacobian(p: np.ndarray, r: np.ndarray) -> np.ndarray:
        jac = np.empty((r.size, p.size))
        for i in range(p.size):
            q = p.copy()
            h = step * max(1.0, abs(p[i]))
            q[i] += h
            jac[:, i] = (fun(q) - r) / h
        return jac

    jac = jacobian(p, r)
    for _ in range(max_iterations):
        a = jac.T @ jac
        g = jac.T @ r
        d = np.diag(a).copy()
        improved = False
        for _ in range(12):
            m = a + lam * np.diag(d + 1e-12 * (d.max() + 1.0))
            try:
                delta = -np.linalg.solve(m, g)
            except np.linalg.LinAlgError:
                lam *= 10
                continue
            r_new = fun(p + delta)
            cost_new = float(r_new @ r_new)
            if np.isfinite(cost_new) and cost_new < cost:
                p, r_old_cost = p + delta, cost
                r, cost = r_new, cost_new
                lam = max(lam / 3, 1e-12)
                improved = True
                break
            lam *= 4
        if not improved:
            break
        jac = jacobian(p, r)
        if r_old_cost - cost <= tolerance * max(r_old_cost, 1e-30):
            break
    return p, jac


def _lifted_init(
    uv: np.ndarray, ground: np.ndarray, centre: Tuple[float, float], scale: float
) -> RadialPlaneModel:
    """Linear start: ground ~ M (x, y, 1, rho^2) solved by a DLT, then H and k1 read off M."""
    x = (uv[:, 0] - centre[0]) / scale
    y = (uv[:, 1] - centre[1]) / scale
    lift = np.column_stack([x, y, np.ones_like(x), x * x + y * y])
    mean = ground.mean(axis=0)
    sd = max(float(ground.std()), 1e-9)
    gx, gy = (ground[:, 0] - mean[0]) / sd, (ground[:, 1] - mean[1]) / sd
    z = np.zeros_like(lift)
    a = np.vstack(
        [
            np.hstack([-lift, z, gx[:, None] * lift]),
            np.hstack([z, -lift, gy[:, None] * lift]),
        ]
    )
    _, _, vt = np.linalg.svd(a)
    m = vt[-1].reshape(3, 4)
    denorm = np.array([[sd, 0, mean[0]], [0, sd, mean[1]], [0, 0, 1.0]])
    m = denorm @ m
    h = m[:, :3]
    k1 = float(m[:, 3] @ m[:, 2] / max(m[:, 2] @ m[:, 2], 1e-30))
    d = np.vstack([x, y, 1 + k1 * (x * x + y * y)])
    return RadialPlaneModel(centre, scale, (k1,), normalise_h(h, d))


def fit_spec(
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    spec: ModelSpec,
    start: Optional[RadialPlaneModel] = None,
    *,
    max_iterations: int = 100,
) -> Fit:
    """Fits one model form to points ``uv`` (M, 2) [px] seen at ``ground`` (M, 2) [m]."""
    w, h = image_size
    centre0 = ((w - 1) / 2.0, (h - 1) / 2.0)
    scale = max(w, h) / 2.0
    if start is None:
        start = _lifted_init(uv, ground, centre0, scale)
    pack = _Packing(spec, centre0, scale)
    fixed_centre = start.centre_px if not spec.free_centre else centre0
    prior_weight = NOISE_PX / CENTRE_PRIOR

    def fun(p: np.ndarray) -> np.ndarray:
        model = pack.unpack(p, fixed_centre)
        r, _ = _residuals(model, uv, ground)
        out = [r.ravel()]
        if spec.free_centre:
            out.append(prior_weight * p[:2])
        return np.concatenate(out)

    p, jac = levenberg_marquardt(fun, pack.pack(start), max_iterations=max_iterations)
    model = pack.unpack(p, fixed_centre)
    d = np.stack(
        [*model.normalised(uv[:, 0], uv[:, 1])]
        + [model.axial(sum(c**2 for c in model.normalised(uv[:, 0], uv[:, 1])))]
    )
    model = RadialPlaneModel(model.centre_px, scale, model.k, normalise_h(model.h, d))
    r, err = _residuals(model, uv, ground)
    return Fit(model, spec, r, err, _linearised_loo(jac, r))


def _linearised_loo(jac: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Leave-one-out prediction error [px] of each point from the Jacobian at the optimum:
    e_i = (I - H_ii)^-1 r_i with the hat matrix H = J (J^T J)^-1 J^T (exact for linear least
    squares; prior rows stay in)."""
    m = r.shape[0]
    a = jac.T @ jac
    a_inv = np.linalg.pinv(a + 1e-12 * np.trace(a) * np.eye(a.shape[0]) / a.shape[0])
    out = np.empty(m)
    for i in range(m):
        ji = jac[2 * i : 2 * i + 2]
        hii = ji @ a_inv @ ji.T
        try:
            e = np.linalg.solve(np.eye(2) - hii, r[i])
        except np.linalg.LinAlgError:
            e = np.full(2, np.inf)
        out[i] = float(np.hypot(*e))
    return out


def fit_best(
    uv: np.ndarray, ground: np.ndarray, image_size: Tuple[int, int]
) -> Tuple[Fit, List[Fit]]:
    """Fits every candidate form that the number of points supports and keeps the one with
    the least leave-one-out RMS [px]. Returns (best, all fits)."""
    m = len(uv)
    fits: List[Fit] = []
    start: Optional[RadialPlaneModel] = None
    for spec in CANDIDATES:
        # At least two equations per parameter and three points spare, or the fit is not
        # checkable (the leave-one-out error explodes).
        if 2 * m < 2 * spec.parameter_count + 6:
            continue
        fit = fit_spec(uv, ground, image_size, spec, start)
        if np.all(np.isfinite(fit.ground_error_m)):
            fits.append(fit)
            start = fit.model
    if not fits:
        need = (2 * CANDIDATES[0].parameter_count + 6 + 1) // 2
        raise CalibrationError(
            f"too few pattern points to fit the camera: {m} found, at least {need} needed "
            f"(use a pattern with more corners or crossings, all inside the image)"
        )

    def loo_rms(f: Fit) -> float:
        return float(np.sqrt(np.mean(f.loo_px**2)))

    best = min(fits, key=loo_rms)
    return best, fits
