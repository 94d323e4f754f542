"""The pose graph's solver, side by side: GTSAM's Levenberg-Marquardt (floorscan's choice)
against SciPy's sparse trust-region least squares (`scipy.optimize.least_squares`, method
"trf", the Jacobian's sparsity given), on the graph floorscan builds from a real laser log
(`floorscan map-log --poses odometry`'s default), both from the same start (the local
trajectory chained), the same cost (whitened residuals, a Cauchy loss of scale 1 on loop
closures). Needs `pip install scipy` besides floorscan[slam].

    .venv/bin/python bench/pose_graph_solvers.py ../shared/data/carmen/freiburg-079-corrected.log.gz
"""

from __future__ import annotations

import argparse
import math
import time

import gtsam
import numpy as np
from floorscan.formats.carmen import read_carmen
from floorscan.formats.carmen_odometry import log_odometry
from floorscan.pipeline.config import Config
from floorscan.pipeline.laser_odometry import graph_of
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix


def chained(edges, first):
    poses = [first]
    for i, _j, m, _, robust in edges:
        if not robust:
            c, s = math.cos(poses[i][2]), math.sin(poses[i][2])
            p = poses[i]
            poses.append((p[0] + c * m[0] - s * m[1], p[1] + s * m[0] + c * m[1], p[2] + m[2]))
    return np.array(poses)


def residuals(x, ii, jj, REL, SG, ROB, first):
    x = x.reshape(-1, 3)
    pi, pj = x[ii], x[jj]
    c, s = np.cos(pi[:, 2]), np.sin(pi[:, 2])
    dx, dy = pj[:, 0] - pi[:, 0], pj[:, 1] - pi[:, 1]
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    cr, sr = np.cos(REL[:, 2]), np.sin(REL[:, 2])
    ex, ey = lx - REL[:, 0], ly - REL[:, 1]
    dyaw = np.remainder(pj[:, 2] - pi[:, 2] - REL[:, 2] + np.pi, 2 * np.pi) - np.pi
    e = np.stack([cr * ex + sr * ey, -sr * ex + cr * ey, dyaw], 1) / SG
    # the Cauchy loss as a scaled residual: 0.5 |w e|^2 = 0.5 log(1 + |e|^2)
    n2 = (e * e).sum(1)
    w = np.where(ROB, np.sqrt(np.log1p(n2) / np.maximum(n2, 1e-300)), 1.0)
    prior = (x[0] - first) / np.array([1e-3, 1e-3, 1e-4])
    return np.concatenate([(e * w[:, None]).ravel(), prior])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    a = ap.parse_args()
    log = read_carmen(a.log)
    # map-log's graph: its default beam limits (40 m, 0.05 m) and [slam.graph] defaults,
    # but round loop closures (`loop_information` off): the least squares here weigh each
    # residual by diagonal standard deviations, so both solvers minimise the same cost
    cfg = Config().with_overrides({"slam.graph.loop_information": False})
    slam = graph_of(log, log_odometry(log).robot_poses, cfg, range_max_m=40.0, range_min_m=0.05)
    edges = slam.graph.edges
    first = np.array(slam.local_poses[0])
    start = chained(edges, tuple(first))
    n = len(start)
    ii = np.array([e[0] for e in edges])
    jj = np.array([e[1] for e in edges])
    REL = np.array([e[2] for e in edges])
    SG = np.array([e[3] for e in edges])
    ROB = np.array([e[4] for e in edges])
    args = (ii, jj, REL, SG, ROB, first)

    def cost(x):
        r = residuals(x.ravel(), *args)
        return 0.5 * float(r @ r)

    print(f"{a.log}: {n} keyframes, {len(edges)} edges, {int(ROB.sum())} loop closures")
    print(f"start: cost {cost(start):.1f}")

    t0 = time.perf_counter()
    graph, values = gtsam.NonlinearFactorGraph(), gtsam.Values()
    prior = gtsam.noiseModel.Diagonal.Sigmas(np.array([1e-3, 1e-3, 1e-4]))
    graph.add(gtsam.PriorFactorPose2(0, gtsam.Pose2(*first), prior))
    for k in range(n):
        values.insert(k, gtsam.Pose2(*start[k]))
    cauchy = gtsam.noiseModel.mEstimator.Cauchy.Create(1.0)
    for i, j, m, sg, robust in edges:
        noise = gtsam.noiseModel.Diagonal.Sigmas(np.array(sg))
        if robust:
            noise = gtsam.noiseModel.Robust.Create(cauchy, noise)
        graph.add(gtsam.BetweenFactorPose2(i, j, gtsam.Pose2(*m), noise))
    result = gtsam.LevenbergMarquardtOptimizer(graph, values).optimize()
    t_gtsam = time.perf_counter() - t0
    xg = np.array(
        [
            [result.atPose2(k).x(), result.atPose2(k).y(), result.atPose2(k).theta()]
            for k in range(n)
        ]
    )
    print(f"GTSAM Levenberg-Marquardt: {t_gtsam:.3f} s, cost {cost(xg):.1f}")

    t0 = time.perf_counter()
    sparsity = lil_matrix((3 * len(edges) + 3, 3 * n), dtype=np.int8)
    for k, (i, j) in enumerate(zip(ii, jj)):
        sparsity[3 * k : 3 * k + 3, 3 * i : 3 * i + 3] = 1
        sparsity[3 * k : 3 * k + 3, 3 * j : 3 * j + 3] = 1
    sparsity[-3:, 0:3] = 1
    res = least_squares(
        residuals, start.ravel(), args=args, jac_sparsity=sparsity, method="trf", x_scale="jac"
    )
    t_scipy = time.perf_counter() - t0
    xs = res.x.reshape(-1, 3)
    gap = np.hypot(*(xs[:, :2] - xg[:, :2]).T).max()
    print(
        f"SciPy least_squares (trf, sparse): {t_scipy:.3f} s, cost {cost(xs):.1f}, "
        f"{res.nfev} evaluations; largest position gap to GTSAM {gap:.3f} m"
    )
    print(f"time SciPy / GTSAM: {t_scipy / t_gtsam:.1f}x")


if __name__ == "__main__":
    main()
