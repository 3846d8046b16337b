# Source this (bash) after scripts/bootstrap: the venv, the built workspace and the
# ROS environment the project runs with. Safe to source more than once.
_fire_uav_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ ! -f "$_fire_uav_root/ros2_ws/install/setup.bash" ]; then
  echo "env.sh: $_fire_uav_root/ros2_ws/install/setup.bash missing: run scripts/bootstrap first" >&2
  return 1 2>/dev/null || exit 1
fi
# shellcheck disable=SC1091
source "$_fire_uav_root/.venv/bin/activate"
export AMENT_PREFIX_PATH="$_fire_uav_root/.venv${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
# setup.bash is not written for 'set -u'
_fire_uav_u=$([[ $- == *u* ]] && echo 1 || echo 0); set +u
# shellcheck disable=SC1091
source "$_fire_uav_root/ros2_ws/install/setup.bash"
[ "$_fire_uav_u" = 1 ] && set -u
# install/setup.bash does not chain the venv prefix (gotcha 3): keep it last.
case ":$AMENT_PREFIX_PATH:" in *":$_fire_uav_root/.venv:"*) ;; *) export AMENT_PREFIX_PATH="$AMENT_PREFIX_PATH:$_fire_uav_root/.venv" ;; esac
export FIRE_UAV_ROOT="$_fire_uav_root"
# this checkout's tools first, even when the venv is shared with another checkout
case ":${PYTHONPATH:-}:" in *":$_fire_uav_root/tools:"*) ;; *) export PYTHONPATH="$_fire_uav_root/tools${PYTHONPATH:+:$PYTHONPATH}" ;; esac
export RMW_IMPLEMENTATION=rmw_fastrtps_cpp
export ROS_LOG_DIR="${ROS_LOG_DIR:-$_fire_uav_root/ros2_ws/log/ros}"
export ROS_AUTOMATIC_DISCOVERY_RANGE="${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}"
export FASTRTPS_DEFAULT_PROFILES_FILE="${FASTRTPS_DEFAULT_PROFILES_FILE:-$_fire_uav_root/config/fastdds_fast_discovery.xml}"
export HOME="${HOME:-$_fire_uav_root}"
unset _fire_uav_root _fire_uav_u
