#!/usr/bin/env bash
# The README's main job: installs what is missing, builds, and runs the demo assembly
# (steel pin through an aluminium plate with a cut corner) through FreeCAD FEM and CalculiX.
# Results go to out/ (or the folder given as the first argument).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build="${ORACLEMESH_BUILD_DIR:-$repo/build}"
out="$(mkdir -p "${1:-$repo/out}" && cd "${1:-$repo/out}" && pwd)"

bash cmake/install-deps.sh
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2
bash cmake/install-workbench.sh "$build"
OUT_DIR="$out" freecadcmd "$repo/examples/demo_assembly.py"
