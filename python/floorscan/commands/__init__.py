"""Command-line subcommands: one module per command, each with ``register(subparsers)``.
``floorscan fleet`` is the fleet package's own (``floorscan.fleet.command``): the fleet runs
``floorscan run`` per recording, so the command sits above both."""

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
    "floorscan.fleet.command",
    "floorscan.commands.node",
    "floorscan.commands.drive",
]
