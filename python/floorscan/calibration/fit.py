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
    def name(self) -> str:
        """e.g. ``radial2`` (centre fixed at the image centre) or ``radial2+centre``."""
        return f"radial{self.terms}" + ("+centre" if self.free_centre else "")

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
    weights = _image_weights(model, uv)
    good = np.all(np.isfinite(e), axis=1) & np.all(np.isfinite(weights), axis=(1, 2))
    r = np.full_like(e, 1e6)
    r[good] = np.einsum("mij,mj->mi", weights[good], e[good])
    return r, np.where(good, np.hypot(e[:, 0], e[:, 1]), np.inf)


def _image_weights(model: RadialPlaneModel, uv: np.ndarray) -> np.ndarray:
    """(M, 2, 2) inverse Jacobians [px/m]: ground errors to image errors; NaN if singular."""
    jac = model.jacobian(uv[:, 0], uv[:, 1])
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    ok = np.isfinite(det) & (np.abs(det) > 1e-18)
    out = np.full_like(jac, np.nan)
    out[ok] = np.linalg.inv(jac[ok])
    return out


def _ground_and_jacobian(
    pack: _Packing, p: np.ndarray, fixed_centre: Tuple[float, float], uv: np.ndarray
) -> Tuple[np.ndarray, np.ndarray]:
    """Model ground points (M, 2) [m] and their derivatives with respect to the packed
    parameters (M, 2, P), analytically."""
    model = pack.unpack(p, fixed_centre)
    x, y = model.normalised(uv[:, 0], uv[:, 1])
    rho2 = x * x + y * y
    z = model.axial(rho2)
    dz_drho2 = np.zeros_like(rho2)
    power = np.ones_like(rho2)
    columns = []
    for n, k in enumerate(model.k, start=1):
        dz_drho2 += n * k * power
        power = power * rho2
        columns.append(power)  # dz/dk_n = rho2^n
    d = np.stack([x, y, z])  # (3, M)
    hm = model.h
    g = hm @ d  # (3, M)
    dg = []  # each (3, M)
    if pack.spec.free_centre:
        dg.append(hm @ np.stack([-np.ones_like(x), np.zeros_like(x), -2 * x * dz_drho2]))
        dg.append(hm @ np.stack([np.zeros_like(x), -np.ones_like(x), -2 * y * dz_drho2]))
    for col in columns:
        dg.append(hm[:, 2:3] * col[None])
    for a in range(3):
        for b in range(3):
            e = np.zeros((3, len(x)))
            e[a] = d[b]
            dg.append(e)
    dg = np.stack(dg, axis=-1)  # (3, M, P)
    w = g[2]
    ground = np.column_stack([g[0] / w, g[1] / w])
    jac = (
        np.stack(
            [
                (dg[0] * w[:, None] - g[0][:, None] * dg[2]),
                (dg[1] * w[:, None] - g[1][:, None] * dg[2]),
            ],
            axis=1,
        )
        / (w * w)[:, None, None]
    )
    return ground, jac


def levenberg_marquardt(
    fun: Callable[[np.ndarray], Tuple[np.ndarray, np.ndarray]],
    p0: np.ndarray,
    *,
    max_iterations: int = 100,
    tolerance: float = 1e-12,
) -> Tuple[np.ndarray, np.ndarray]:
    """Minimises ``sum(r^2)`` where ``fun(p) = (r, dr/dp)``, from ``p0``; returns (p, dr/dp
    at p). Marquardt's diagonal scaling."""
    p = np.asarray(p0, float).copy()
    r, jac = fun(p)
    cost = float(r @ r)
    lam = 1e-3
    for _ in range(max_iterations):
        a = jac.T @ jac
        g = jac.T @ r
        d = np.diag(a).copy()
        improved = False
        previous = cost
        for _ in range(12):
            m = a + lam * np.diag(d + 1e-12 * (d.max() + 1.0))
            try:
                delta = -np.linalg.solve(m, g)
            except np.linalg.LinAlgError:
                lam *= 10
                continue
            r_new, jac_new = fun(p + delta)
            cost_new = float(r_new @ r_new)
            if np.isfinite(cost_new) and cost_new < cost:
                p, r, jac, cost = p + delta, r_new, jac_new, cost_new
                lam = max(lam / 3, 1e-12)
                improved = True
                break
            lam *= 4
        if not improved or previous - cost <= tolerance * max(previous, 1e-30):
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
    rounds: int = 3,
    with_loo: bool = True,
) -> Fit:
    """Fits one model form to points ``uv`` (M, 2) [px] seen at ``ground`` (M, 2) [m].
    ``rounds`` solves, each with the image weights of the previous one's result; the
    linearised leave-one-out errors only ``with_loo``."""
    w, h = image_size
    centre0 = ((w - 1) / 2.0, (h - 1) / 2.0)
    scale = max(w, h) / 2.0
    if start is None:
        start = _lifted_init(uv, ground, centre0, scale)
    pack = _Packing(spec, centre0, scale)
    fixed_centre = start.centre_px if not spec.free_centre else centre0
    prior_weight = NOISE_PX / CENTRE_PRIOR
    p = pack.pack(start)
    model = start
    # Residuals are ground errors turned into image errors by each point's inverse Jacobian,
    # held fixed within a solve and updated between solves.
    for _round in range(rounds):
        weights = _image_weights(model, uv)
        if not np.all(np.isfinite(weights)):
            break

        def fun(q: np.ndarray, weights=weights):
            g, dg = _ground_and_jacobian(pack, q, fixed_centre, uv)
            e = g - ground
            r = np.einsum("mij,mj->mi", weights, e).ravel()
            jr = np.einsum("mij,mjp->mip", weights, dg).reshape(r.size, -1)
            bad = ~np.isfinite(r)
            if np.any(bad):
                r = np.where(bad, 1e6, r)
                jr = np.where(np.isfinite(jr), jr, 0.0)
            if spec.free_centre:
                prior_j = np.zeros((2, q.size))
                prior_j[0, 0] = prior_j[1, 1] = prior_weight
                r = np.concatenate([r, prior_weight * q[:2]])
                jr = np.vstack([jr, prior_j])
            return r, jr

        p_new, jac = levenberg_marquardt(fun, p, max_iterations=max_iterations)
        step = np.max(np.abs(p_new - p))
        p = p_new
        model = pack.unpack(p, fixed_centre)
        if step < 1e-9:
            break
    d = np.stack(
        [*model.normalised(uv[:, 0], uv[:, 1])]
        + [model.axial(sum(c**2 for c in model.normalised(uv[:, 0], uv[:, 1])))]
    )
    model = RadialPlaneModel(model.centre_px, scale, model.k, normalise_h(model.h, d))
    r, err = _residuals(model, uv, ground)
    loo = _linearised_loo(jac, r) if with_loo else np.full(len(uv), np.nan)
    return Fit(model, spec, r, err, loo)


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
    """Fits every candidate form that the number of points supports and keeps the simplest
    whose leave-one-out RMS [px] is within 2 % of the least. Returns (best, all fits)."""
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

    # The simplest form within 2 % of the best leave-one-out error: more terms that do not
    # predict held-out points better only add freedom where there is no data.
    least = min(loo_rms(f) for f in fits)
    best = next(f for f in fits if loo_rms(f) <= 1.02 * least)
    return best, fits


OUTLIER_PX = 1.0
"""Residuals below this [px] are never outliers (detector noise on real images)."""


def fit_robust(
    uv: np.ndarray, ground: np.ndarray, image_size: Tuple[int, int]
) -> Tuple[Fit, List[Fit], np.ndarray]:
    """:func:`fit_best`, then once more without the points whose residual exceeds both
    ``OUTLIER_PX`` and five robust standard deviations (a corner the detector misplaced), if
    they are at most a tenth of the points. Returns (best, all fits, used-point mask)."""
    best, fits = fit_best(uv, ground, image_size)
    r = np.hypot(best.residual_px[:, 0], best.residual_px[:, 1])
    scale = 1.4826 * float(np.median(r))
    bad = r > max(OUTLIER_PX, 5 * scale)
    used = np.ones(len(uv), bool)
    if np.any(bad) and bad.sum() <= max(1, len(uv) // 10):
        used = ~bad
        best, fits = fit_best(uv[used], ground[used], image_size)
    return best, fits, used
