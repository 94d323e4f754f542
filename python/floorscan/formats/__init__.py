"""Files other tools read and write: images, ROS map_server maps, CARMEN logs, ROS bags, TUM
trajectories, the dataset folder and its rig file (docs/formats.md)."""
