# SPDX-License-Identifier: BSD-3-Clause
# A ROS master of the calling script's own on localhost:PORT, so that the script neither needs nor disturbs a
# running ROS system (scripts/demo, soak, bench, camera_restarts, check-install-space). Source this after the ROS
# setup (roscore and rostopic on PATH), and set the script's EXIT trap, calling uws_stop_master, before starting:
#   uws_start_master WHO PORT LOG [HINT]
#       exports ROS_HOSTNAME=localhost and ROS_MASTER_URI=http://localhost:PORT; refuses (uws_refuse_master: status 2)
#       when a master already answers there: one left by a killed run would take the script's launch and hide a
#       failure. Starts roscore (its output in LOG) and returns once the master answers, or fails (status 1) with
#       LOG's last lines if roscore exits first (the port taken by something else, say).
#   uws_refuse_master WHO PORT [HINT]
#       the check alone, for a script that starts its master late but should learn of a taken port early: status 2,
#       and "WHO: ..." and HINT on stderr, when a master answers on PORT.
#   uws_stop_master
#       stops the master started (SIGINT, then waits for it); nothing when none was started, so safe in any trap.
uws_master_pid=

uws_refuse_master() {
  local who=$1 port=$2 hint=${3:-}
  if ROS_MASTER_URI=http://localhost:$port ROS_HOSTNAME=localhost rostopic list >/dev/null 2>&1; then
    echo "$who: a ROS master already answers on port $port (left by an earlier run?): stop it${hint:+, $hint}" >&2
    return 2
  fi
}

uws_start_master() {
  local who=$1 port=$2 log=$3 hint=${4:-}
  export ROS_HOSTNAME=localhost ROS_MASTER_URI=http://localhost:$port
  uws_refuse_master "$who" "$port" "$hint" || return
  roscore -p "$port" >"$log" 2>&1 &
  uws_master_pid=$!
  until rostopic list >/dev/null 2>&1; do
    if ! kill -0 "$uws_master_pid" 2>/dev/null; then
      echo "$who: roscore on port $port exited: $(tail -n 3 "$log")" >&2
      uws_master_pid=
      return 1
    fi
    sleep 0.5
  done
}

uws_stop_master() {
  if [[ -n $uws_master_pid ]]; then
    { kill -INT "$uws_master_pid" 2>/dev/null && wait "$uws_master_pid" 2>/dev/null; } || true  # its status is not ours
    uws_master_pid=
  fi
  return 0
}
