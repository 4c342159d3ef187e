#!/usr/bin/env bash
# Installs the Debian 12 packages corridorsim needs. Idempotent: a quick no-op when all are
# present. Run as root (or with sudo available).
set -euo pipefail

PACKAGES=(
  # toolchain
  cmake g++ ninja-build pkg-config clang-format ccache
  # libraries (see ../shared/DEPENDENCIES.md)
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libboost-math-dev libopencv-dev libbullet-dev liboctomap-dev
  libosmesa6-dev libegl-dev libegl-mesa0 libgl-dev
  libfreetype-dev fonts-dejavu-core
  catch2
  # plots; the example detector of the README (examples/)
  python3-matplotlib python3-opencv
  # the Python package's tests (python/tests, docs/protocol.md)
  python3-pytest python3-numpy
  # the Debian packages `cpack` makes (docs/install.md): dpkg-shlibdeps computes their Depends
  dpkg-dev file
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

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
