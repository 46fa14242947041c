# Shared by scripts/demo, scripts/test and the benchmarks: environment, install, build.
# Source it; it defines functions only, apart from the environment below.

# Debian's ROS lives under /usr; pyenv's python3 cannot import rospy, and CMake's FindPython3
# must not find it either.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
export PYTHONNOUSERSITE=1
unset PYTHONPATH PYENV_VERSION

GRANULAR_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WORKSPACE="${GRANULAR_ROOT}/ros_ws"
export GRANULAR_ROOT WORKSPACE

log() { printf '\033[1m==> %s\033[0m\n' "$*" >&2; }
die() { printf 'error: %s\n' "$*" >&2; exit 1; }

# Install the Debian packages of scripts/debian-packages.txt that are missing; no network and no
# root needed when nothing is.
install_packages() {
  local wanted missing=()
  mapfile -t wanted < <(grep -v '^\s*#' "${GRANULAR_ROOT}/scripts/debian-packages.txt" | grep -v '^\s*$')
  for package in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "${package}" 2>/dev/null | grep -q "install ok installed" \
      || missing+=("${package}")
  done
  [ "${#missing[@]}" -eq 0 ] && return 0
  [ "$(id -u)" -eq 0 ] || die "missing Debian packages (${missing[*]}); run as root or install them"
  log "installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Build the workspace with catkin_make (devel space) and make it the current environment.
build_workspace() {
  local logfile="${WORKSPACE}/build/catkin_make.log"
  mkdir -p "${WORKSPACE}/build"
  log "building ${WORKSPACE} with catkin_make (log: ${logfile})"
  if ! (cd "${WORKSPACE}" && catkin_make -DCMAKE_BUILD_TYPE=Release \
          -DPYTHON_EXECUTABLE=/usr/bin/python3 -j"$(nproc)") >"${logfile}" 2>&1; then
    tail -n 60 "${logfile}" >&2
    die "catkin_make failed; the full log is ${logfile}"
  fi
  use_workspace
}

# The same workspace through colcon (python3-colcon-ros), in its own build and install spaces.
build_workspace_with_colcon() {
  local logfile="${WORKSPACE}/build_colcon.log"
  log "building ${WORKSPACE} with colcon (log: ${logfile})"
  if ! (cd "${WORKSPACE}" && colcon build --build-base build_colcon --install-base install_colcon \
          --cmake-args -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
          -DCATKIN_ENABLE_TESTING=OFF) >"${logfile}" 2>&1; then
    tail -n 60 "${logfile}" >&2
    die "colcon build failed; the full log is ${logfile}"
  fi
}

# `run_tool PACKAGE EXECUTABLE ARGS...` runs what `rosrun` would, without rosrun's look-up
# (about half a second a call): the executable catkin_make put in the devel space, or rosrun
# where there is none. Not for `&`: the tool would run in a subshell that `kill` does not reach.
run_tool() {
  local executable="${WORKSPACE}/devel/lib/$1/$2"
  if [ -f "${executable}" ] && [ -x "${executable}" ]; then
    shift 2
    "${executable}" "$@"
  else
    rosrun "$@"
  fi
}

use_workspace() {
  set +u
  # shellcheck disable=SC1091
  source "${WORKSPACE}/devel/setup.bash"
  set -u
}
