"""``--rerun``: log frames, boundary points, scans and maps to a Rerun recording so a run can be
scrubbed through (optional extra: ``pip install 'floorscan[rerun]'``)."""

from __future__ import annotations

import numpy as np

from ..errors import OptionError
from ..ranging.scan import ColumnStatus


class RerunOutputs:
    """Wraps :class:`~floorscan.pipeline.outputs.RunOutputs`, logging each frame to Rerun too and
    saving the recording as ``run.rrd`` in the output folder."""

    def __init__(self, inner) -> None:
        try:
            import rerun as rr
        except ImportError:
            raise OptionError(
                "--rerun needs the rerun-sdk package: pip install 'floorscan[rerun]'"
            ) from None
        self.rr = rr
        self.inner = inner
        self.out = inner.out
        rr.init("floorscan", spawn=False)
        rr.save(str(self.out / "run.rrd"))

    def on_frame(self, frame, scan, pose, mapper) -> None:
        self.inner.on_frame(frame, scan, pose, mapper)
        rr = self.rr
        rr.set_time("time", timestamp=scan.timestamp) if hasattr(
            rr, "set_time"
        ) else rr.set_time_seconds("time", scan.timestamp)
        rr.log("camera/image", rr.Image(frame.image))
        ok = scan.status_codes == ColumnStatus.BOUNDARY
        rr.log(
            "camera/boundary",
            rr.Points2D(
                np.stack([scan.columns[ok].astype(float), scan.rows[ok]], axis=1), radii=2.0
            ),
        )
        pts = np.stack([scan.x[ok], scan.y[ok]], axis=1)
        rr.log("robot/scan", rr.Points2D(pts, radii=0.01))
        if pose is not None:
            rr.log("world/robot", rr.Points2D([[pose[0], pose[1]]], radii=0.05))

    def finish(self, mapper, stats) -> None:
        self.inner.finish(mapper, stats)
        self.rr.log("world/map", self.rr.Image(mapper.global_map.to_rgb()))
