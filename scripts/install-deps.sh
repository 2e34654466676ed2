#!/usr/bin/env bash
# Installs the Debian bookworm packages rubcont needs, and only those that are missing.
# Idempotent: when everything is present it takes about 0.1 s and touches nothing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev coinor-libipopt-dev libnlopt-cxx-dev libsundials-dev libhdf5-dev catch2
  libtomlplusplus-dev libcli11-dev libfmt-dev libboost-dev
  python3-matplotlib python3-h5py python3-numpy
  pybind11-dev python3-dev python3-pytest
  python3-xarray python3-h5netcdf python3-mpi4py python3-tqdm
  libopenmpi-dev openmpi-bin
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
if [ "$(id -u)" -ne 0 ]; then
  SUDO=sudo
else
  SUDO=
fi
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
