"""The map builder: scans plus odometry into log-odds occupancy grids.

:class:`~floorscan.mapping.grid.OccupancyGrid` (global), :class:`~floorscan.mapping.local_map.LocalMap`
(robot-fixed), the evidence options, read-only views, and the unclamped evidence maps that merge
recordings exactly.
"""
