"""A fleet's recordings mapped as Ray tasks (or in-process) and merged into one map
(docs/fleet.md)."""
