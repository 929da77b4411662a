#!/usr/bin/env bash
# Install what Marble needs to build and test, from Debian 12's own apt
# repositories, and only what is missing (checked with dpkg -s).
#
#   bash maintainer/install_deps.sh          # install the missing packages
#   source maintainer/install_deps.sh        # define the functions only:
#     marble_missing_packages                # print the missing ones
#     marble_install_deps                    # install them (apt-get update first)
#
# Used by maintainer/quickstart.sh, maintainer/run_tests.sh and .ci/run, so the
# list lives here only.

MARBLE_DEB_PACKAGES=(
  cmake g++ make
  libboost-dev libfftw3-dev libhdf5-openmpi-dev libopenmpi-dev openmpi-bin
  pybind11-dev librandom123-dev libgtest-dev
  python3-dev python3-numpy python3-scipy python3-h5py python3-matplotlib python3-pytest
  python3-mdanalysis python3-hypothesis python3-meshio python3-sympy
  python3-sphinx python3-myst-parser python3-nbsphinx pandoc jupyter-nbconvert python3-ipykernel
)

marble_missing_packages() {
  local p
  for p in "${MARBLE_DEB_PACKAGES[@]}"; do
    if ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
      echo "$p"
    fi
  done
}

marble_install_deps() {
  local missing
  missing=$(marble_missing_packages | tr '\n' ' ')
  if [[ -z "${missing// /}" ]]; then
    echo "[deps] all ${#MARBLE_DEB_PACKAGES[@]} Debian packages are installed"
    return 0
  fi
  echo "[deps] missing: ${missing}"
  local sudo=()
  if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null 2>&1; then
      sudo=(sudo)
    else
      echo "[deps] error: not root and no sudo; install as root: apt-get install ${missing}" >&2
      return 1
    fi
  fi
  export DEBIAN_FRONTEND=noninteractive
  # shellcheck disable=SC2086  # word splitting of the package list is intended
  "${sudo[@]}" apt-get update &&
    "${sudo[@]}" apt-get install -y --no-install-recommends ${missing}
}

if [[ "${BASH_SOURCE[0]}" == "$0" ]]; then
  set -euo pipefail
  marble_install_deps
fi
