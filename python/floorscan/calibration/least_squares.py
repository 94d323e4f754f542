"""Levenberg-Marquardt least squares (numpy only), used by the camera fit."""

from __future__ import annotations

from typing import Callable, Tuple

import numpy as np


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
