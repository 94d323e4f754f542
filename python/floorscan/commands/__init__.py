"""Command-line subcommands: one module per command, each with ``register(subparsers)``."""

COMMAND_MODULES = [
    "floorscan.commands.scan",
    "floorscan.commands.overlay",
    "floorscan.commands.demo",
    "floorscan.commands.config",
    "floorscan.commands.run",
    "floorscan.commands.map_log",
    "floorscan.commands.calibrate",
    "floorscan.commands.sim",
    "floorscan.commands.eval",
    "floorscan.commands.tune",
    "floorscan.commands.merge",
    "floorscan.commands.fleet",
    "floorscan.commands.node",
    "floorscan.commands.drive",
]
