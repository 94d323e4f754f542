"""floorscan.drive: the camera's maps in closed loop. A simulated robot follows a world's tour
with only its camera (through the ranger and the ground table), its odometry and an avoidance
map, through a dynamic-window local planner on a costmap with inflation; the simulator judges
contact from truth. ``sensor="laser"`` drives the same planner with an ideal 2-D laser.

>>> from floorscan.drive import DriveOptions, drive
>>> from floorscan.sim import World
>>> result = drive(World.builtin("room"), DriveOptions(seconds=2, table="exact"))
>>> sorted(k for k in result.summary() if k in ("collisions", "distance_m"))
['collisions', 'distance_m']
"""

from ..mapping.scan_matcher import MatchResult, ScanMatcher, ScanMatcherOptions
from .avoidance_map import AvoidanceMap, AvoidanceMapOptions
from .costmap import CostmapOptions, inflate, navigation_function
from .dwa import DwaOptions, choose_velocity
from .loop import SENSORS, TABLES, DriveOptions, drive, make_table
from .result import DriveResult
from .sensor_model import VisualSensorModel
from .solids import Solids

__all__ = [
    "SENSORS",
    "TABLES",
    "AvoidanceMap",
    "AvoidanceMapOptions",
    "CostmapOptions",
    "DriveOptions",
    "DriveResult",
    "DwaOptions",
    "MatchResult",
    "ScanMatcher",
    "ScanMatcherOptions",
    "Solids",
    "VisualSensorModel",
    "choose_velocity",
    "drive",
    "inflate",
    "make_table",
    "navigation_function",
]
