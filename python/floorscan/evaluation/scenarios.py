"""The evaluation suite: simulated scenarios, each a world under one lighting, sensor noise,
lens and odometry setting, with a seed.

The full suite varies one factor at a time around the default on the carpet world (the
``corridor``) and runs every built-in world at the defaults; worlds that break an assumption
of the paper (an overhanging table, paper scraps and linoleum doorways, tiles, wooden planks, a patterned
carpet) are tagged so the
report lists them separately. ``quick_suite`` is a small subset that runs in seconds.
"""

from __future__ import annotations

import re
from dataclasses import asdict, dataclass, replace
from typing import Dict, List, Optional, Tuple

from ..errors import OptionError
from ..ranging.lens import CameraMount, Lens
from ..sim import Camera, Imaging, OdometryNoise, Robot, World

# What each built-in world tests; anything but "carpet" breaks an assumption of the paper.
WORLD_GROUPS: Dict[str, str] = {
    "corridor": "carpet",
    "room": "overhanging table",
    "lab": "paper scraps, linoleum doorways",
    "tiles": "tiled floor",
    "parquet": "wooden plank floor",
    "patterned": "patterned carpet",
}
CARPET = "carpet"
TEXTURED_WORLDS = ("tiles", "parquet", "patterned")
"""The worlds whose floor breaks the texture assumption with a pattern of its own: the suite
also drives them faster (the floor-parallax cue's case, issue 39)."""
DEFAULT_SPEED_MPS = 0.3
FAST_SPEED_MPS = 0.5

# Lighting: (exposure, exposure jitter) written into the world's [lighting] table.
LIGHTING: Dict[str, Tuple[float, float]] = {
    "dim": (0.45, 0.08),
    "normal": (1.0, 0.03),
    "bright": (1.5, 0.08),
    "shadowed": (1.0, 0.03),
}
# More of the [lighting] table, per lighting: "shadowed" darkens the floor towards the foot of
# every solid standing on it (docs/simulator.md, "Contact shadows"): half the light at the
# foot, falling to 1/e of that in 4 cm (the real cabinet of issue 13: its shadow starts ~5
# rows of 480 before its base).
LIGHTING_EXTRA: Dict[str, Dict[str, str]] = {
    "shadowed": {"contact_shadow": "{ strength = 0.5, length_m = 0.04 }"},
}
# Sensor noise: (read noise [DN], shot noise gain [DN]).
NOISE: Dict[str, Tuple[float, float]] = {
    "low": (0.5, 0.02),
    "default": (1.5, 0.06),
    "high": (4.0, 0.25),
}
LENSES = ("fisheye", "wide")
# Odometry: OdometryNoise fields (wheel sigma, scale error, radius difference, wheelbase error).
ODOMETRY: Dict[str, Tuple[float, float, float, float]] = {
    "perfect": (0.0, 0.0, 0.0, 0.0),
    "default": (0.01, 0.01, 0.004, 0.02),
    "drifting": (0.03, 0.03, 0.012, 0.06),
}


@dataclass(frozen=True)
class Scenario:
    """One simulated run to evaluate.

    - ``world``: built-in world name.
    - ``lighting``: key of :data:`LIGHTING` (dim, normal, bright, shadowed: normal light with
      contact shadows).
    - ``noise``: key of :data:`NOISE` (low, default, high).
    - ``lens``: ``fisheye`` (the simulator's default Kannala-Brandt, ~136 degrees) or ``wide``
      (a plumb-bob pinhole of ~100 degrees with barrel distortion).
    - ``odometry``: key of :data:`ODOMETRY` (perfect, default, drifting).
    - ``seed``: simulation seed.
    - ``seconds``: simulated time [s] (frames at 10 Hz).
    - ``speed_mps``: the robot's cruise speed [m/s], in (0, 3]. Default 0.3 (the paper's).
    """

    world: str
    lighting: str = "normal"
    noise: str = "default"
    lens: str = "fisheye"
    odometry: str = "default"
    seed: int = 0
    seconds: float = 30.0
    speed_mps: float = DEFAULT_SPEED_MPS

    def __post_init__(self) -> None:
        for value, table, what in (
            (self.world, WORLD_GROUPS, "world"),
            (self.lighting, LIGHTING, "lighting"),
            (self.noise, NOISE, "noise"),
            (self.lens, dict.fromkeys(LENSES), "lens"),
            (self.odometry, ODOMETRY, "odometry"),
        ):
            if value not in table:
                raise OptionError(f"invalid {what} {value!r}: expected one of {sorted(table)}")
        if not self.seconds > 0:
            raise OptionError(f"invalid seconds: must be > 0, got {self.seconds}")
        if not 0 < self.speed_mps <= 3:
            raise OptionError(f"invalid speed_mps: must be in (0, 3], got {self.speed_mps}")

    @property
    def name(self) -> str:
        parts = [self.world]
        for value, default in (
            (self.lighting, "normal"),
            (self.noise, "default"),
            (self.lens, "fisheye"),
            (self.odometry, "default"),
        ):
            if value != default:
                parts.append(value)
        if self.speed_mps != DEFAULT_SPEED_MPS:
            parts.append(f"{self.speed_mps:g}mps")
        return "-".join(parts) + f"-s{self.seed}"

    @property
    def group(self) -> str:
        return WORLD_GROUPS[self.world]

    @property
    def breaks_assumption(self) -> bool:
        return self.group != CARPET

    def as_dict(self) -> Dict[str, object]:
        d = asdict(self)
        d.update(name=self.name, group=self.group)
        return d

    # --- simulator objects ------------------------------------------------------------
    def build_world(self):
        world = World.builtin(self.world)
        if self.lighting == "normal":
            return world
        exposure, jitter = LIGHTING[self.lighting]
        return World.from_toml(
            with_lighting(
                builtin_world_text(self.world),
                exposure,
                jitter,
                LIGHTING_EXTRA.get(self.lighting),
            ),
            source_name=f"{self.world} ({self.lighting})",
        )

    def build_camera(self):
        read, shot = NOISE[self.noise]
        imaging = Imaging(read_noise_dn=read, shot_noise_gain=shot)
        if self.lens == "fisheye":
            return Camera(imaging=imaging)
        # ~100 degrees horizontally on 320 x 240, barrel distortion, looking down a little
        # more than the fisheye so the floor in front of the robot is in view.
        lens = Lens.pinhole_radial(
            fx=150.0, fy=150.0, cx=159.5, cy=119.5, k1=-0.28, k2=0.07, p1=0.0, p2=0.0
        )
        return Camera(lens=lens, mount=CameraMount(height_m=0.4, tilt_rad=0.75), imaging=imaging)

    def build_robot(self):
        sigma, scale, diff, base = ODOMETRY[self.odometry]
        return Robot(
            speed_mps=self.speed_mps,
            odometry=OdometryNoise(
                wheel_sigma_per_sqrt_m=sigma,
                radius_scale_error=scale,
                radius_difference=diff,
                wheelbase_error=base,
            ),
        )


def builtin_world_text(name: str) -> str:
    """The TOML text of a built-in world (its ``source``, else the crate's world file)."""
    from pathlib import Path

    text = World.builtin(name).source
    if text:
        return text
    repo = Path(__file__).resolve().parents[3]
    path = repo / "crates" / "floorscan-sim" / "worlds" / f"{name}.toml"
    if not path.is_file():
        raise OptionError(f"cannot vary the lighting of {name!r}: its world file is not available")
    return path.read_text(encoding="utf-8")


def with_lighting(
    text: str, exposure: float, jitter: float, extra: Optional[Dict[str, str]] = None
) -> str:
    """World TOML with ``exposure`` and ``exposure_jitter`` set in its ``[lighting]`` table
    (added when absent), and the keys of ``extra`` (TOML values as text) set there too."""
    values: Dict[str, str] = {"exposure": repr(exposure), "exposure_jitter": repr(jitter)}
    values.update(extra or {})
    lines = text.splitlines()
    out: List[str] = []
    in_lighting = False
    seen = set()

    def flush() -> None:
        for key, value in values.items():
            if key not in seen:
                out.append(f"{key} = {value}")

    keys = "|".join(re.escape(k) for k in values)
    for line in lines:
        stripped = line.strip()
        if stripped.startswith("["):
            if in_lighting:
                flush()
            in_lighting = stripped == "[lighting]"
            seen = set()
        elif in_lighting:
            m = re.match(rf"({keys})\s*=", stripped)
            if m:
                key = m.group(1)
                seen.add(key)
                line = f"{key} = {values[key]}"
        out.append(line)
    if in_lighting:
        flush()
    if "[lighting]" not in (s.strip() for s in lines):
        out += ["[lighting]"] + [f"{k} = {v}" for k, v in values.items()]
    return "\n".join(out) + "\n"


def full_suite(*, seconds: float = 30.0, seeds: Tuple[int, ...] = (0, 1, 2)) -> List[Scenario]:
    """Every built-in world at the defaults for each seed, plus one factor at a time varied on
    the carpet world (corridor) with the first seed, the second lens on every world, and the
    textured floors driven at 0.5 m/s (:data:`TEXTURED_WORLDS`; 0.3 m/s, the paper's speed,
    otherwise). (The tour is the same for every seed; seeds change the sensor noise, exposure
    jitter and odometry errors.)"""
    out: List[Scenario] = []
    for world in WORLD_GROUPS:
        for seed in seeds:
            out.append(Scenario(world, seed=seed, seconds=seconds))
    variations = [
        {"lighting": "dim"},
        {"lighting": "bright"},
        {"noise": "low"},
        {"noise": "high"},
        {"lighting": "dim", "noise": "high"},
        {"lens": "wide"},
        {"odometry": "perfect"},
        {"odometry": "drifting"},
        {"lighting": "shadowed"},
    ]
    for change in variations:
        out.append(replace(Scenario("corridor", seed=seeds[0], seconds=seconds), **change))
    for world in WORLD_GROUPS:
        if world != "corridor":
            out.append(Scenario(world, lens="wide", seed=seeds[0], seconds=seconds))
    # contact shadows where furniture stands on the floor (chairs, tables, boxes)
    out.append(Scenario("room", lighting="shadowed", seed=seeds[0], seconds=seconds))
    # textured floors driven faster, with the default odometry noise
    for world in TEXTURED_WORLDS:
        out.append(Scenario(world, seed=seeds[0], seconds=seconds, speed_mps=FAST_SPEED_MPS))
    return out


def quick_suite(*, seconds: Optional[float] = None) -> List[Scenario]:
    """A small suite (a few hundred frames): the carpet world at the defaults and in dim light
    with high noise, and the room with its overhanging table."""
    s = 10.0 if seconds is None else seconds
    return [
        Scenario("corridor", seconds=s),
        Scenario("corridor", lighting="dim", noise="high", seed=1, seconds=s),
        Scenario("room", seconds=s),
    ]
