# SPDX-License-Identifier: BSD-3-Clause
"""A ROS master of the calling script's own on localhost:PORT (scripts/bench_pipeline, scripts/malformed_inputs),
as private_master.bash gives the shell scripts: the script neither needs nor disturbs a running ROS system.

    core = start_master(who, port, log)   # ... then, in a finally: stop_master(core)

start_master sets ROS_HOSTNAME=localhost and ROS_MASTER_URI=http://localhost:PORT in os.environ (so rospy and the
processes started later use it) and refuses, exiting with "WHO: ..." naming the port, when a master already answers
there: one left by a killed run would take the script's launch and hide a failure. It starts roscore (its output to
`log`, a file or subprocess.DEVNULL) and returns its Popen once the master answers, or exits with roscore's status
if roscore exits first (the port taken by something else, say).
"""
import os
import subprocess
import sys
import time

import rosgraph


def start_master(who, port, log):
    uri = "http://localhost:%d" % port
    os.environ.update(ROS_MASTER_URI=uri, ROS_HOSTNAME="localhost")
    if rosgraph.is_master_online(uri):
        sys.exit("%s: a ROS master already answers on port %d (left by an earlier run?): stop it" % (who, port))
    core = subprocess.Popen(["roscore", "-p", str(port)], stdout=log, stderr=subprocess.STDOUT)
    while not rosgraph.is_master_online(uri):
        if core.poll() is not None:
            sys.exit("%s: roscore on port %d exited with status %d" % (who, port, core.returncode))
        time.sleep(0.3)
    return core


def stop_master(core):
    """Stops a master start_master started (SIGINT, as Ctrl-C would, then waits for it)."""
    core.send_signal(2)
    core.wait()
