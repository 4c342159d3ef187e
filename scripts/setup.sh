#!/usr/bin/env bash
# Installs the Debian 12 packages corridorsim needs. Idempotent: a quick no-op when all are
# present. Run as root (or with sudo available).
set -euo pipefail

PACKAGES=(
  # toolchain
  cmake g++ ninja-build pkg-config clang-format ccache
  # libraries (see ../shared/DEPENDENCIES.md)
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libboost-math-dev libopencv-dev libbullet-dev liboctomap-dev libpng-dev libjpeg-dev
  libceres-dev
  # recordings (docs/recordings.md): MCAP's chunk compression; ROS 1 bags through rosbag_storage
  # with the ROS message headers; python3-rosbag reads them back in the tests
  libzstd-dev liblz4-dev
  librosbag-storage-dev libsensor-msgs-dev libgeometry-msgs-dev libnav-msgs-dev libtf2-msgs-dev
  libvisualization-msgs-dev python3-rosbag
  libosmesa6-dev libegl-dev libegl-mesa0 libgl-dev
  libfreetype-dev fonts-dejavu-core
  catch2
  # plots; the example detector of the README (examples/)
  python3-matplotlib python3-opencv
  # the Python package's tests (python/tests, docs/protocol.md)
  python3-pytest python3-numpy
  # the Python package's analysis side (corridorsim.Run, Study, Dataset: docs/analysis.md)
  python3-pandas
  # the Debian packages `cpack` makes (docs/install.md): dpkg-shlibdeps computes their Depends
  dpkg-dev file
  # the viewer's browser tests (docs/viewer.md): Debian's Chromium, driven headless by
  # playwright-core from npm (viewer/package-lock.json, installed below)
  chromium
  # `corridorsim study --slurm`'s test: a single-node Slurm on this machine
  # (scripts/slurm_local.sh, tests/slurm/)
  munge slurm-client slurmctld slurmd
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm (for viewer/): the machine's Node.js when it has one (it may come from elsewhere than Debian,
# with its own npm), else Debian's nodejs and npm.
if ! command -v npm > /dev/null 2>&1; then missing+=(nodejs npm); fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The viewer's npm packages, exactly as viewer/package-lock.json pins them (uPlot, inlined into
# every viewer.html; playwright-core, which drives Debian's chromium in the browser tests):
# `npm ci` when viewer/node_modules does not hold that lockfile's packages.
here="$(cd "$(dirname "$0")/.." && pwd)"
# The node on PATH must run what the lockfile pins (each package's `engines.node`): say so here
# rather than let a browser test fail on it later.
if ! node "$here/scripts/check_node_engines.js" "$here/viewer/package-lock.json"; then
  echo "setup: the Node.js on PATH ($(command -v node), $(node --version)) cannot run the packages" \
       "viewer/package-lock.json pins (above); install a Node.js they accept or pin versions that" \
       "accept this one (docs/viewer.md)" >&2
  exit 1
fi
if ! cmp -s "$here/viewer/package-lock.json" "$here/viewer/node_modules/.corridorsim-lock.json"; then
  echo "setup: npm ci in viewer/"
  (cd "$here/viewer" && npm ci --no-audit --no-fund --loglevel=error)
  cp "$here/viewer/package-lock.json" "$here/viewer/node_modules/.corridorsim-lock.json"
fi
