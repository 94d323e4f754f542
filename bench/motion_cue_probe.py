"""A probe of issue 39's motion cue before it is built: does floor-plane parallax tell a floor's
own edges (grout, plank joints) from obstacles' bases? numpy, per frame, not the product.

For each sampled column the edge ranger's boundary is tested against two explanations of the
image rows above it, between the current frame and one `--gap` frames before:
- floor: every pixel is floor, so it moved as the ground table and the motion predict;
- obstacle: the pixels stand on a vertical surface through the edge's ground point B, along
  the base line drawn by the neighbouring columns' boundaries (facing the camera where there
  are none nearby). A pixel whose ray meets the floor at G (camera ground frame, origin under
  the camera) meets that surface at s G; in the earlier frame its ray meets the floor at
  M(s G) / s (M the earlier camera frame from the current one). Neither needs the camera's
  height or a pinhole: only the table.
The edge is the floor's own (vetoed, and the column scanned on above it) when the floor explains
the patch's zero-mean intensities better: the log-likelihood ratio summed over the pairs (each
at the floor's residual sigma) exceeds `--min-llr` and at least `--agree` of the pairs that
could tell favour the floor. A patch without texture keeps the edge ranger's reading. The
motion M comes from odometry, refined by Lucas-Kanade on the floor within 1 m of the camera.

    .venv/bin/python bench/motion_cue_probe.py --worlds tiles corridor parquet --seeds 1 2
    .venv/bin/python bench/motion_cue_probe.py --worlds bench/worlds/office_l.toml --floor tiles

Prints, per world and seed, the share of sampled columns wrong (status, or > 10 cm;
`floorscan.evaluation.scoring.score_columns`) for the edge ranger alone and with the veto.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import cv2
import numpy as np
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.case import case_from_run
from floorscan.evaluation.scenarios import builtin_world_text
from floorscan.evaluation.scoring import score_columns
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config
from floorscan.sim import Camera, World, simulate_run

# Floors the simulator's built-in worlds do not use (held out from the probe's choices).
HELD_OUT_FLOORS = {
    "tiles": (
        'kind = "tiles"\nbrightness = 0.55\ntile_m = 0.45\ngrout_m = 0.006\n'
        "grout_brightness = 0.3\nvariation = 0.18\n"
    ),
    "wood": (
        'kind = "wood"\nbrightness = 0.45\nplank_m = 0.18\nlength_m = 1.1\ngrain = 0.12\n'
        "variation = 0.16\njoint_m = 0.003\njoint_brightness = 0.28\n"
    ),
}


def load_world(spec: str, floor: str) -> World:
    text = Path(spec).read_text() if spec.endswith(".toml") else None
    if text is None:
        if floor == "as-is":
            return World.builtin(spec)
        text = builtin_world_text(spec)
    if floor != "as-is":
        swapped, n = re.subn(r'(\[floor\]\s*\ncovering\s*=\s*)"[^"]*"', r'\1"probe_floor"', text)
        if n == 0:
            if re.search(r"^\[floor\]", text, re.M):
                raise SystemExit(f"{spec}: its [floor] table does not start with `covering`")
            swapped = text + '\n[floor]\ncovering = "probe_floor"\n'
        text = swapped + "\n[coverings.probe_floor]\n" + HELD_OUT_FLOORS[floor]
    return World.from_toml(text, source_name=f"{spec} ({floor})")


def se2(p) -> np.ndarray:
    x, y, t = p
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])


def bilinear(img: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    h, w = img.shape
    u = np.clip(u, 0, w - 1.001)
    v = np.clip(v, 0, h - 1.001)
    u0, v0 = np.floor(u).astype(int), np.floor(v).astype(int)
    fu, fv = u - u0, v - v0
    return (
        img[v0, u0] * (1 - fu) * (1 - fv)
        + img[v0, u0 + 1] * fu * (1 - fv)
        + img[v0 + 1, u0] * (1 - fu) * fv
        + img[v0 + 1, u0 + 1] * fu * fv
    )


def table_jacobian(table, u, v, h=0.5):
    x, y = table.lookup(u, v)
    xu, yu = table.lookup(u + h, v)
    xv, yv = table.lookup(u, v + h)
    return x, y, (xu - x) / h, (xv - x) / h, (yu - y) / h, (yv - y) / h


def inverse_lookup(table, gx, gy, u0, v0, iters=6):
    """The pixels whose ground point is (gx, gy): Newton's method from (u0, v0); NaN where it
    does not converge to within 1 mm."""
    u, v = u0.astype(float).copy(), v0.astype(float).copy()
    for _ in range(iters):
        x, y, a, b, c, d = table_jacobian(table, u, v)
        det = a * d - b * c
        ex, ey = gx - x, gy - y
        u += np.clip(np.nan_to_num((d * ex - b * ey) / det), -20, 20)
        v += np.clip(np.nan_to_num((-c * ex + a * ey) / det), -20, 20)
    x, y = table.lookup(u, v)
    bad = ~(np.hypot(x - gx, y - gy) < 1e-3)
    u[bad] = np.nan
    v[bad] = np.nan
    return u, v


def refine_motion(table, cur, prv, m, band, iters=5):
    """Lucas-Kanade: a left SE(2) correction of m (earlier from current) that aligns the floor
    within `band` (pixel mask) of the two frames."""
    vv, uu = np.nonzero(band)
    u, v = uu.astype(float), vv.astype(float)
    x, y = table.lookup(u, v)
    target = cur[vv, uu]
    gy_img, gx_img = np.gradient(prv)
    for _ in range(iters):
        gp = m @ np.stack([x, y, np.ones(x.size)])
        up, vp = inverse_lookup(table, gp[0], gp[1], u, v)
        ok = np.isfinite(up)
        _, _, a, b, c, d = table_jacobian(table, up, vp)
        det = a * d - b * c
        upn, vpn = np.nan_to_num(up), np.nan_to_num(vp)
        ip, gx, gy = (bilinear(i, upn, vpn) for i in (prv, gx_img, gy_img))
        dix = gx * d / det + gy * -c / det
        diy = gx * -b / det + gy * a / det
        j = np.stack([dix, diy, -dix * gp[1] + diy * gp[0]], 1)
        r = target - ip
        sel = ok & np.isfinite(j).all(1) & (np.hypot(gx, gy) > 2.0)
        if sel.sum() < 50:
            return m
        w = 1 / np.maximum(1, np.abs(r[sel]) / 10)
        a_mat = (j[sel] * w[:, None]).T @ j[sel]
        delta = np.linalg.solve(
            a_mat + np.eye(3) * 1e-6 * np.trace(a_mat), (j[sel] * w[:, None]).T @ r[sel]
        )
        m = se2(delta) @ m
        if np.abs(delta).max() < 1e-4:
            break
    return m


def floor_noise(table, cur, prv, m, band):
    """Robust sigma of the floor band's residual after the warp [grey levels]: the frame's
    noise, the two views' resolution and lighting and what is left of the motion's error."""
    vv, uu = np.nonzero(band)
    u, v = uu.astype(float), vv.astype(float)
    x, y = table.lookup(u, v)
    gp = m @ np.stack([x, y, np.ones(x.size)])
    up, vp = inverse_lookup(table, gp[0], gp[1], u, v)
    ok = np.isfinite(up)
    r = cur[vv[ok], uu[ok]] - bilinear(prv, up[ok], vp[ok])
    return float(1.4826 * np.median(np.abs(r - np.median(r))))


def zero_mean_residual(table, cur, prv, u, v, g_prev):
    up, vp = inverse_lookup(table, g_prev[0], g_prev[1], u, v)
    ok = np.isfinite(up)
    if ok.sum() < 0.7 * ok.size:
        return np.nan
    a, b = bilinear(cur, u[ok], v[ok]), bilinear(prv, up[ok], vp[ok])
    return float(np.sqrt(np.mean(((a - a.mean()) - (b - b.mean())) ** 2)))


def pair_llr(table, cur, prv, m, u, vb, along, *, rows_above, texture, noise_sigma, min_parallax):
    """The log-likelihood ratio that the rows above edge row vb of column u moved as floor
    rather than as a vertical surface standing at vb (0 where the pair cannot tell)."""
    vs = np.arange(vb - rows_above, vb, dtype=float)
    if vs.min() < 0:
        return 0.0
    vg, ug = np.meshgrid(vs, np.arange(u - 1, u + 2, dtype=float))
    uf, vf = ug.ravel(), vg.ravel()
    gx, gy = table.lookup(uf, vf)
    bx, by = table.lookup(np.full_like(uf, u), np.full_like(vf, vb))
    if not (np.all(np.isfinite(gx)) and np.all(np.isfinite(bx))):
        return 0.0
    if bilinear(cur, uf, vf).std() < texture:
        return 0.0
    ones = np.ones_like(gx)
    floor = (m @ np.stack([gx, gy, ones]))[:2]
    # the surface: vertical, through the base point B, along the direction `along` (the base
    # line of the neighbouring columns' boundaries; None: facing the camera); a ray meeting the
    # floor at G meets it at s G
    d = np.array([-by[0], bx[0]]) if along is None else np.asarray(along, float)
    cross = gx * d[1] - gy * d[0]
    s = (bx * d[1] - by * d[0]) / np.where(np.abs(cross) > 1e-9, cross, np.nan)
    if not np.all((s > 0.05) & (s <= 1.0)):
        return 0.0
    standing = (m @ np.stack([s * gx, s * gy, ones]))[:2] / s
    if min_parallax > 0:
        # the two explanations must put the patch's pixels apart in the earlier frame, else
        # the test cannot tell them apart (pure rotation, a short baseline, a low patch)
        fu, fv = inverse_lookup(table, floor[0], floor[1], uf, vf)
        su, sv = inverse_lookup(table, standing[0], standing[1], uf, vf)
        # what the earlier frame's gradient says the two explanations differ by: a texture
        # that runs along the difference (a skirting parallel to the motion, the aperture
        # problem) cannot tell them apart however far apart they put it
        gy_img, gx_img = np.gradient(prv)
        ok = np.isfinite(fu) & np.isfinite(su)
        if ok.sum() < 0.7 * ok.size:
            return 0.0
        gxs = bilinear(gx_img, fu[ok], fv[ok])
        gys = bilinear(gy_img, fu[ok], fv[ok])
        apart = np.sqrt(np.mean((gxs * (su - fu)[ok] + gys * (sv - fv)[ok]) ** 2))
        if not (apart >= min_parallax):
            return 0.0
    rf = zero_mean_residual(table, cur, prv, uf, vf, floor)
    ro = zero_mean_residual(table, cur, prv, uf, vf, standing)
    if not (np.isfinite(rf) and np.isfinite(ro)):
        return 0.0
    # the log-likelihood ratio of floor over a standing surface, Gaussian residuals of the
    # floor's sigma
    return float(uf.size * (ro**2 - rf**2) / (2 * noise_sigma**2))


def floor_explains(table, cur, pairs, u, vb, along, args) -> bool:
    """The edge at row vb of column u is the floor's own: over the pairs (earlier frame,
    motion, floor sigma) the summed log-likelihood ratio exceeds `--min-llr` and at least
    `--agree` of the pairs that could tell favour the floor."""
    llrs = [
        pair_llr(
            table,
            cur,
            prv,
            m,
            u,
            vb,
            along,
            rows_above=args.rows_above,
            texture=args.texture,
            noise_sigma=sigma,
            min_parallax=args.min_parallax,
        )
        for prv, m, sigma in pairs
    ]
    told = [x for x in llrs if x != 0.0]
    if not told:
        return False
    agree = np.mean([x > 0 for x in told])
    return bool(sum(llrs) > args.min_llr and agree >= args.agree)


def base_direction(scan, j, max_gap_m=0.25):
    """The direction of the base line at column j from its neighbours' boundary points (None
    where they are not boundaries near it)."""
    pts = [
        (scan.x[i], scan.y[i])
        for i in (j - 1, j + 1)
        if 0 <= i < len(scan.x) and scan.status_codes[i] == 0
    ]
    here = np.array([scan.x[j], scan.y[j]])
    near = [np.array(p) for p in pts if np.hypot(*(np.array(p) - here)) < max_gap_m]
    if len(near) == 2:
        d = near[1] - near[0]
    elif len(near) == 1:
        d = near[0] - here
    else:
        return None
    n = np.hypot(*d)
    return d / n if n > 1e-6 else None


def scan_with_motion(table, ranger, img, cur, pairs, args, max_vetoes=10):
    work = img.copy()
    scan = ranger.scan(work)
    cols = scan.columns.astype(int)
    open_cols = np.ones(len(cols), bool)
    for _ in range(max_vetoes):
        changed = False
        for j, c in enumerate(cols):
            if not open_cols[j] or scan.status_codes[j] != 0:
                open_cols[j] = False
                continue
            vb = float(scan.rows[j])
            if floor_explains(table, cur, pairs, c, vb, base_direction(scan, j), args):
                # the edge is the floor's: flatten the column below it and scan on above it
                v = int(round(vb)) - 1
                work[v:, max(0, c - 3) : c + 4] = work[v, max(0, c - 3) : c + 4]
                changed = True
            else:
                open_cols[j] = False
        if not changed:
            break
        scan = ranger.scan(work)
    return scan


def probe(world, seed, args):
    cfg = Config()
    camera = Camera(width=args.width, height=args.height)
    run = simulate_run(world, camera=camera, seconds=args.seconds, seed=seed, threads=2)
    table, _ = calibrated_table(camera, calibration=cfg.calibration.kwargs())
    case = case_from_run("probe", run, table, cell_size_m=cfg.grid.cell_size_m)
    ranger = ranger_from_config(table, cfg)
    h, w = np.asarray(case.images[0]).shape
    vv, uu = np.mgrid[0:h, 0:w].astype(float)
    x, y = table.lookup(uu, vv)
    band = np.isfinite(x) & (np.hypot(x, y) < 1.0)
    mount = se2(case.robot_from_camera)
    wrong = {"edge": [0, 0], "motion": [0, 0]}
    for k in range(max(args.gaps), len(case), args.stride):
        img = np.asarray(case.images[k])
        cur = cv2.GaussianBlur(img.astype(np.float32), (0, 0), 1.0)
        odo = case.odometry
        pairs = []
        for gap in args.gaps:
            prv = cv2.GaussianBlur(np.asarray(case.images[k - gap]).astype(np.float32), (0, 0), 1.0)
            m = np.linalg.inv(mount) @ np.linalg.inv(se2(odo[k - gap])) @ se2(odo[k]) @ mount
            m = refine_motion(table, cur, prv, m, band)
            pairs.append((prv, m, max(floor_noise(table, cur, prv, m, band), 0.5)))
        for key, scan in (
            ("edge", ranger.scan(img)),
            ("motion", scan_with_motion(table, ranger, img, cur, pairs, args)),
        ):
            sc = score_columns(scan, case.true_status[k], case.true_points[k])
            wrong[key][0] += int(sc.wrong.sum())
            wrong[key][1] += sc.wrong.size
    return {k: v[0] / v[1] for k, v in wrong.items()}, wrong["edge"][1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", nargs="+", default=["tiles", "corridor", "parquet"])
    ap.add_argument("--floor", choices=["as-is", *HELD_OUT_FLOORS], default="as-is")
    ap.add_argument("--seeds", nargs="+", type=int, default=[1])
    ap.add_argument("--seconds", type=float, default=8.0)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--stride", type=int, default=5, help="score every n-th frame")
    ap.add_argument(
        "--gaps",
        nargs="+",
        type=int,
        default=[6],
        help="frames between the current view and each earlier one (10 Hz)",
    )
    ap.add_argument(
        "--agree",
        type=float,
        default=0.0,
        help="least share of the pairs that could tell which favour the floor",
    )
    ap.add_argument("--rows-above", type=int, default=30)
    ap.add_argument("--texture", type=float, default=2.0)
    ap.add_argument(
        "--min-llr",
        type=float,
        default=0.0,
        help="least log-likelihood ratio of floor over a standing surface for a veto",
    )
    ap.add_argument(
        "--min-parallax",
        type=float,
        default=0.0,
        help="least RMS intensity difference [grey levels] the earlier frame's gradient predicts between the two explanations, for a veto",
    )
    args = ap.parse_args()
    for spec in args.worlds:
        world = load_world(spec, args.floor)
        for seed in args.seeds:
            r, n = probe(world, seed, args)
            print(
                f"{spec} ({args.floor}) seed {seed}: {n} columns, edge {100 * r['edge']:.1f} % "
                f"-> with the motion veto {100 * r['motion']:.1f} %",
                flush=True,
            )


if __name__ == "__main__":
    main()
