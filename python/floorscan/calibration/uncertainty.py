"""Error bars of a calibration, per table node: how far the floor point the table gives may be
from the true one [m]. Three parts:

1. **Parameter uncertainty**: the fit's covariance propagated to the node's floor point
   (linearised, ``J C J^T``); the bar is ``SIGMAS`` times the standard deviation along the
   error ellipse's major axis (``SIGMAS = 2.15`` holds 90 % of a circular 2-D Gaussian, more
   of an elongated one).
2. **Model uncertainty**: the largest distance between the chosen family's floor point and
   that of every other plausible family (one that predicts held-out pattern points about as
   well, :mod:`.model_choice`) whose likelihood ratio on the held-out points is at least
   ``MIN_WEIGHT`` (:func:`family_weights`): where the pattern cannot tell the lenses apart
   the bar says so.
3. **Interpolation**: the table interpolates bilinearly between nodes; the largest difference
   from the model at the midpoints of the cells around a node.

The bar is ``alpha * hypot(1, 2) + 3``, where ``alpha >= 1`` makes the bars honest on data
the fit has not seen: the same bars computed for the cross-validation refits at the pattern
points they held out must cover 90 % of those points' actual errors (a conformal
calibration of the linearised bars on extrapolation by one block).
"""

from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

from .camera_fit import CameraFit
from .camera_model import CameraModel

MIN_WEIGHT = 0.05
"""Plausible families less likely than this (likelihood ratio on the held-out points) do not
count into the model part."""
SIGMAS = 2.15
"""Standard deviations in the bar (90 % of a circular 2-D Gaussian)."""


def floor_points(
    model: CameraModel, u: np.ndarray, v: np.ndarray, *, min_depression_rad: float
) -> np.ndarray:
    """(2, ...) floor points of pixels, NaN where the model has none."""
    return np.stack(model.ground(u, v, min_depression_rad=min_depression_rad))


def parameter_sigma(
    fit: CameraFit, u: np.ndarray, v: np.ndarray, *, min_depression_rad: float
) -> np.ndarray:
    """Standard deviation [m] of each pixel's floor point along its error ellipse's major
    axis, from the fit's covariance."""
    p0 = fit.model.vector()
    idx = np.nonzero(fit.free)[0]
    jac = np.empty((2,) + np.shape(u) + (idx.size,))
    for c, i in enumerate(idx):
        h = 1e-6 * max(abs(p0[i]), 1.0)
        a, b = p0.copy(), p0.copy()
        a[i] += h
        b[i] -= h
        ga = floor_points(fit.model.with_vector(a), u, v, min_depression_rad=min_depression_rad)
        gb = floor_points(fit.model.with_vector(b), u, v, min_depression_rad=min_depression_rad)
        jac[..., c] = (ga - gb) / (2 * h)
    # Sigma_g = J C J^T per pixel (2 x 2), its largest eigenvalue.
    jc = np.einsum("x...p,pq->x...q", jac, fit.covariance)
    sxx = np.einsum("...p,...p->...", jc[0], jac[0])
    syy = np.einsum("...p,...p->...", jc[1], jac[1])
    sxy = np.einsum("...p,...p->...", jc[0], jac[1])
    half_trace = 0.5 * (sxx + syy)
    lam = half_trace + np.sqrt(np.maximum(0.25 * (sxx - syy) ** 2 + sxy * sxy, 0))
    return np.sqrt(np.maximum(lam, 0))


def model_spread(
    best: CameraModel,
    others: Sequence[CameraModel],
    u: np.ndarray,
    v: np.ndarray,
    *,
    min_depression_rad: float,
    weights: Optional[Sequence[float]] = None,
    fold_margin_px: float = 0.0,
) -> np.ndarray:
    """Largest distance [m] between ``best``'s floor point and each of ``others``' whose
    weight (if ``weights`` are given) is at least ``MIN_WEIGHT``: infinite where such a model
    sees the pixel's ray at or above the horizon while ``best`` sees floor (a disagreement
    that matters), not counted where the model's lens cannot describe the pixel (past the
    radius where its polynomial folds back, or within ``fold_margin_px`` of it: it is no
    candidate for that part of the image).

    The margin matters because a lens polynomial flattens as it nears its fold, so its
    inverse there turns a pixel into a ray far from its neighbours' (a simulated fisheye's
    pinhole-k3 candidate: 15 cm off at the last node before its fold, 2 cm one node in). Such
    nodes would raise isolated bars, and so holes, inside a table that is trusted all around
    them. :func:`node_errors` passes the table's node spacing."""
    g = floor_points(best, u, v, min_depression_rad=min_depression_rad)
    out = np.zeros(np.shape(u))
    for i, m in enumerate(others):
        if weights is not None and weights[i] < MIN_WEIGHT:
            continue
        o = floor_points(m, u, v, min_depression_rad=min_depression_rad)
        d = np.hypot(o[0] - g[0], o[1] - g[1])
        describable = _describable(m, u, v, fold_margin_px)
        d = np.where(describable, np.where(np.isfinite(d), d, np.inf), 0.0)
        out = np.maximum(out, d)
    return out


def _describable(model: CameraModel, u, v, margin_px: float) -> np.ndarray:
    """Where ``model``'s lens gives a ray at the pixel and at the eight pixels ``margin_px``
    around it."""
    u, v = np.asarray(u, float), np.asarray(v, float)
    steps = (-margin_px, 0.0, margin_px) if margin_px > 0 else (0.0,)
    ok = np.ones(np.shape(u), bool)
    for du in steps:
        for dv in steps:
            ok &= np.all(np.isfinite(model.rays(u + du, v + dv)), axis=0)
    return ok


def family_weights(choice) -> Tuple[List[CameraModel], List[float]]:
    """The other plausible families and their weights: ``exp(-delta / 2)`` with ``delta`` the
    excess of their held-out squared errors over the chosen family's, in units of its mean
    held-out squared error (a likelihood ratio on the held-out points)."""
    best = choice.best
    e0 = best.held_out_errors_px
    var = max(float(np.mean(e0 * e0)), 1e-12)
    ss0 = float(np.sum(e0 * e0))
    others, weights = [], []
    for c in choice.plausible:
        if c is best:
            continue
        delta = (float(np.sum(c.held_out_errors_px**2)) - ss0) / var
        others.append(c)
        weights.append(float(np.exp(-0.5 * max(delta, 0.0))))
    return others, weights


def interpolation_error(
    model: CameraModel, spacing_px: int, u: np.ndarray, v: np.ndarray, *, min_depression_rad: float
) -> np.ndarray:
    """Per node (grid ``u``, ``v`` (nodes_v, nodes_u)), the largest distance [m] between the
    model and the bilinear interpolation of the nodes at the centres and edge midpoints of
    the four cells around it."""
    s = float(spacing_px)
    g = floor_points(model, u, v, min_depression_rad=min_depression_rad)
    nv, nu = u.shape
    cell = np.zeros((nv - 1, nu - 1))
    for fu, fv in ((0.5, 0.5), (0.5, 0.0), (0.0, 0.5), (0.5, 1.0), (1.0, 0.5)):
        mu = u[:-1, :-1] + fu * s
        mv = v[:-1, :-1] + fv * s
        m = floor_points(model, mu, mv, min_depression_rad=min_depression_rad)
        b = (
            (1 - fu) * (1 - fv) * g[:, :-1, :-1]
            + fu * (1 - fv) * g[:, :-1, 1:]
            + (1 - fu) * fv * g[:, 1:, :-1]
            + fu * fv * g[:, 1:, 1:]
        )
        d = np.hypot(m[0] - b[0], m[1] - b[1])
        cell = np.maximum(cell, np.where(np.isfinite(d), d, 0.0))
    out = np.zeros((nv, nu))
    for dj in (0, 1):
        for di in (0, 1):
            out[dj : dj + nv - 1, di : di + nu - 1] = np.maximum(
                out[dj : dj + nv - 1, di : di + nu - 1], cell
            )
    return out


def node_errors(
    fit: CameraFit,
    plausible: Sequence[CameraModel],
    u: np.ndarray,
    v: np.ndarray,
    spacing_px: int,
    *,
    min_depression_rad: float,
    alpha: float = 1.0,
    weights: Optional[Sequence[float]] = None,
) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(bar, parameter part, model part, interpolation part) [m] at the nodes; ``alpha``
    scales the first two (:func:`inflation`); ``weights``: of the ``plausible`` models
    (:func:`family_weights`; None: the largest distance counts)."""
    sigma = SIGMAS * parameter_sigma(fit, u, v, min_depression_rad=min_depression_rad)
    spread = model_spread(
        fit.model,
        plausible,
        u,
        v,
        min_depression_rad=min_depression_rad,
        weights=weights,
        fold_margin_px=float(spacing_px),
    )
    interp = interpolation_error(fit.model, spacing_px, u, v, min_depression_rad=min_depression_rad)
    return alpha * np.hypot(sigma, spread) + interp, sigma, spread, interp


COVERAGE = 0.90
"""Fraction of held-out pattern points the calibrated bars must cover."""
MIN_INFLATION = 0.5
"""The linearised bars shrink by at most this factor when held-out points say they are too
wide."""


def inflation(choice, uv: np.ndarray, ground: np.ndarray, *, fold_margin_px: float = 0.0) -> float:
    """``alpha`` (>= 1): the factor by which the bars of the cross-validation refits must grow
    to cover ``COVERAGE`` of their held-out points' floor errors; ``fold_margin_px`` as the
    bars it scales (:func:`model_spread`)."""
    best = choice.best
    plausible, weights = family_weights(choice)
    used_uv, used_g = uv[choice.used], ground[choice.used]
    ratios: List[np.ndarray] = []
    for k, test in enumerate(choice.folds):
        f = best.fold_fits[k]
        u, v = used_uv[test, 0], used_uv[test, 1]
        x, y = f.model.ground(u, v)
        e = np.hypot(x - used_g[test, 0], y - used_g[test, 1])
        sigma = SIGMAS * parameter_sigma(f, u, v, min_depression_rad=0.0)
        spread = model_spread(
            f.model,
            [c.fold_fits[k].model for c in plausible],
            u,
            v,
            min_depression_rad=0.0,
            weights=weights,
            fold_margin_px=fold_margin_px,
        )
        bar = np.hypot(sigma, spread)
        ratios.append(np.where(np.isfinite(e), e, np.inf) / np.maximum(bar, 1e-9))
    r = np.concatenate(ratios)
    if r.size == 0:
        return 1.0
    return float(np.clip(np.quantile(r, COVERAGE), MIN_INFLATION, 10.0))
