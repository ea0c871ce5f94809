#!/usr/bin/env bash
# Installs every Debian 12 package OracleMesh builds, tests or compares against.
# Non-interactive and idempotent: packages already present are skipped, so the
# README's two commands can call it on every run.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config
  # core libraries
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev
  nlohmann-json3-dev libgtest-dev zlib1g-dev
  # Python module (built for the system interpreter FreeCAD embeds)
  python3-dev pybind11-dev python3-numpy python3-pytest python3-meshio
  # FreeCAD FEM and its solver
  freecad calculix-ccx
  # peers for comparisons and benchmarks; examples/implant_in_bone/measure.py (KD-tree)
  gmsh tetgen python3-netgen python3-scipy
  # fuzzing the job parser and the file readers (tests/fuzz: clang's libFuzzer)
  clang libclang-rt-14-dev
  # GUI tests (workbench under a virtual display); matplotlib also draws the batch plots
  xvfb xauth python3-matplotlib
  # batch studies (oraclemesh batch) run on Dask
  python3-distributed
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/tmp/oraclemesh-apt.log 2>&1 || {
  tail -40 /tmp/oraclemesh-apt.log >&2
  echo "install-deps: apt-get install failed (full log: /tmp/oraclemesh-apt.log)" >&2
  exit 1
}
echo "install-deps: done"
