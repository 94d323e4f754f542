"""Choosing the lens family: every candidate is fitted (outliers set aside first, once for all),
then scored by how well it predicts pattern points it was not fitted to: block cross-validation
that holds out the farthest, nearest, leftmost and rightmost points in turn (extrapolation, the
thing a table beyond the pattern needs), in pixels. The simplest family within
``PARSIMONY`` of the best score wins; the others that predict about as well stay as the
"plausible" set whose disagreement counts into the error bars (:mod:`.uncertainty`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..errors import CalibrationError
from .camera_fit import CameraFit, fit_family, refine
from .lens_family import FAMILIES

PARSIMONY = 1.10
"""A simpler family wins if its held-out error is within this factor of the best."""
PLAUSIBLE = 1.25
"""Families whose held-out error is within this factor of the chosen one's are plausible."""
OUTLIER_PX = 1.0
"""Residuals below this [px] are never outliers."""
OUTLIER_SIGMAS = 4.0
"""... nor those within this many robust standard deviations."""
MAX_OUTLIER_FRACTION = 0.2
DESCRIBED_SLACK = 0.01
"""Families describing this much less of the image than the widest are passed over."""
CV_RMS_FACTOR = 2.0
"""Families whose residual RMS exceeds the best's by this factor are not cross-validated."""
HOLD_OUT = 0.15
"""Fraction of the points in each cross-validation block."""


@dataclass
class Candidate:
    """One family: its fit on the used points and its held-out error [px] (RMS)."""

    name: str
    fit: CameraFit
    held_out_px: float
    held_out_errors_px: np.ndarray
    fold_fits: List[CameraFit]


@dataclass
class Choice:
    best: Candidate
    candidates: List[Candidate]
    used: np.ndarray
    folds: List[np.ndarray]

    @property
    def plausible(self) -> List[Candidate]:
        """The chosen family and every other that predicts held-out points about as well."""
        bound = PLAUSIBLE * self.best.held_out_px
        return [c for c in self.candidates if c is self.best or c.held_out_px <= bound]


def blocks(ground: np.ndarray, centre_xy: np.ndarray) -> List[np.ndarray]:
    """Held-out masks: the farthest, nearest, leftmost and rightmost ``HOLD_OUT`` of the
    points as seen from the camera (range and bearing about ``centre_xy``)."""
    d = ground - centre_xy[None]
    rng = np.hypot(d[:, 0], d[:, 1])
    bearing = np.arctan2(d[:, 1], d[:, 0])
    k = max(1, int(round(HOLD_OUT * len(ground))))
    out = []
    for key in (-rng, rng, -bearing, bearing):
        m = np.zeros(len(ground), bool)
        m[np.argsort(key, kind="stable")[:k]] = True
        out.append(m)
    return out


def held_out(
    fit: CameraFit,
    uv: np.ndarray,
    ground: np.ndarray,
    image_size,
    folds: Sequence[np.ndarray],
    *,
    fix_lens: bool = False,
) -> Tuple[np.ndarray, List[CameraFit]]:
    """Pixel errors of each held-out point (one per point per fold, concatenated), the model
    refitted without the fold's points; and those refits."""
    errors = []
    fits = []
    for test in folds:
        train = ~test
        f = refine(
            fit.model,
            uv[train],
            ground[train],
            image_size,
            fix_lens=fix_lens,
            max_iterations=30,
            noise_px=fit.noise_px,
        )
        fits.append(f)
        u, v = f.model.project_ground(ground[test, 0], ground[test, 1])
        e = np.hypot(u - uv[test, 0], v - uv[test, 1])
        errors.append(np.where(np.isfinite(e), e, 1e4))
    return np.concatenate(errors), fits


def described_share(model, image_size: Tuple[int, int], step_px: int = 16) -> float:
    """Share of the image (a lattice every ``step_px``) where the lens model is valid."""
    w, h = image_size
    v, u = np.mgrid[0:h:step_px, 0:w:step_px].astype(float)
    return float(np.mean(np.all(np.isfinite(model.rays(u, v)), axis=0)))


def reject_outliers(residual_px: np.ndarray) -> np.ndarray:
    """Inlier mask of (M, 2) residuals [px] (robust scale; at most ``MAX_OUTLIER_FRACTION``
    of the points out)."""
    r = np.hypot(residual_px[:, 0], residual_px[:, 1])
    r = np.where(np.isfinite(r), r, np.inf)
    scale = 1.4826 * float(np.median(r))
    bad = r > max(OUTLIER_PX, OUTLIER_SIGMAS * scale)
    if bad.sum() > MAX_OUTLIER_FRACTION * len(r):
        worst = np.argsort(-r)[: int(MAX_OUTLIER_FRACTION * len(r))]
        bad = np.zeros_like(bad)
        bad[worst] = True
    return ~bad


def choose(
    uv: np.ndarray,
    ground: np.ndarray,
    image_size: Tuple[int, int],
    families: Sequence[str],
    *,
    lens: Optional[np.ndarray] = None,
) -> Choice:
    """Fits each family (or the one family with known ``lens`` intrinsics, pose only), sets
    outliers aside, scores by block cross-validation and chooses."""
    specs = [FAMILIES[f] for f in families]
    min_points = 8 if lens is not None else 12
    if len(uv) < min_points:
        raise CalibrationError(
            f"too few pattern points to fit the camera: {len(uv)} found, at least {min_points} "
            "needed (use a pattern with more corners or crossings, all inside the image)"
        )
    fits: Dict[str, CameraFit] = {}
    for spec in specs:
        try:
            fits[spec.name] = fit_family(spec, uv, ground, image_size, lens=lens)
        except CalibrationError:
            continue
    if not fits:
        raise CalibrationError(
            "no lens model fits the pattern's points with the camera above the floor: the "
            "pattern is mirrored (check `near_left`, `yaw` and the counts) or not on the floor"
        )
    # Outliers from the family that reproduces the points best, then every family refitted
    # without them (so all are judged on the same points).
    reference = min(fits.values(), key=lambda f: f.rms_px)
    used = reject_outliers(reference.residual_px)
    for _ in range(3):
        if used.all():
            break
        reference = refine(
            reference.model, uv[used], ground[used], image_size, fix_lens=lens is not None
        )
        u, v = reference.model.project_ground(ground[:, 0], ground[:, 1])
        again = reject_outliers(np.column_stack([u, v]) - uv)
        if np.array_equal(again, used):
            break
        used = again
    if used.sum() < len(uv):
        fits = {
            n: refine(f.model, uv[used], ground[used], image_size, fix_lens=lens is not None)
            for n, f in fits.items()
        }
    # Families that reproduce the points far worse than the best cannot be chosen nor be
    # plausible: no cross-validation for them.
    best_rms = min(f.rms_px for f in fits.values())
    fits = {n: f for n, f in fits.items() if f.rms_px <= CV_RMS_FACTOR * best_rms}
    u_uv, u_g = uv[used], ground[used]
    centre = next(iter(fits.values())).model.centre_m[:2]
    folds = blocks(u_g, centre)
    cands = []
    for n, f in fits.items():
        e, ff = held_out(f, u_uv, u_g, image_size, folds, fix_lens=lens is not None)
        cands.append(Candidate(n, f, float(np.sqrt(np.mean(e * e))), e, ff))
    least = min(c.held_out_px for c in cands)
    near = [c for c in cands if c.held_out_px <= PARSIMONY * least]
    # A lens model that folds back inside the image cannot describe its rim: among those that
    # predict about as well, the ones that describe the whole image come first.
    described = {c.name: described_share(c.fit.model, image_size) for c in near}
    widest = max(described.values())
    near = [c for c in near if described[c.name] >= widest - DESCRIBED_SLACK]
    fewest = min(len(c.fit.model.family.terms) for c in near)
    best = min(
        (c for c in near if len(c.fit.model.family.terms) == fewest), key=lambda c: c.held_out_px
    )
    return Choice(best, cands, used, folds)
