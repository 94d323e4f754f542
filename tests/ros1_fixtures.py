"""A real ROS 1 master for the node's tests: ``roscore`` on a free port, started and stopped
around a test module, and rospy in this process (Debian's python3-rospy, with the real
sensor_msgs / nav_msgs classes: an implementation independent of floorscan's codec)."""

from __future__ import annotations

import importlib
import os
import shutil
import socket
import subprocess
import time

import pytest


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


ROS1_MODULES = (
    "rosgraph",
    "genpy",
    "sensor_msgs.msg",
    "nav_msgs.msg",
    "tf2_msgs.msg",
    "rosbags.typesys",
)
"""Every module the ROS 1 node's tests import besides rospy (the tests' own imports and the
node's: rosgraph and genpy by the node, rosbags for its message codec): one missing is a skip
(a machine with a partial ROS 1, e.g. without ros-noetic-tf2-msgs, skips, never fails)."""


def require_ros1():
    """rospy and every module of ROS1_MODULES, or a skip naming what is missing."""
    from floorscan.errors import MiddlewareError
    from floorscan.node.ros1 import import_rospy

    if shutil.which("roscore") is None:
        pytest.skip("ROS 1 is not installed: no roscore (apt-get install ros-core python3-rospy)")
    try:
        rospy = import_rospy()
    except MiddlewareError as e:
        pytest.skip(f"ROS 1 Python packages missing: {e}")
    for module in ROS1_MODULES:
        try:
            importlib.import_module(module)
        except ImportError as e:
            pytest.skip(f"ROS 1 Python packages missing: {module} ({e})")
    return rospy


class Roscore:
    def __init__(self, tmp_path) -> None:
        import rosgraph

        self.port = free_port()
        self.uri = f"http://127.0.0.1:{self.port}"
        self.env = dict(os.environ, ROS_MASTER_URI=self.uri, ROS_HOME=str(tmp_path / "ros_home"))
        self.proc = subprocess.Popen(
            ["roscore", "-p", str(self.port)],
            env=self.env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        deadline = time.monotonic() + 30
        while not rosgraph.is_master_online(self.uri):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.stop()
                pytest.skip("roscore did not start")
            time.sleep(0.1)

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, 2)
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, 9)
                self.proc.wait()
