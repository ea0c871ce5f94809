#!/usr/bin/env bash
# Makes FreeCAD find the OracleMesh workbench and the built core module:
#   ~/.local/share/FreeCAD/Mod/OracleMesh/   (a real directory, FreeCAD's user Mod folder)
#     Init.py, InitGui.py, package.xml, oraclemesh_fc  -> symlinks into the repo's Mod/OracleMesh
#     icons                                            -> symlink to the repo's icons/
#     oraclemesh                                       -> symlink to BUILD_DIR/python/oraclemesh
# FreeCAD puts each Mod folder on sys.path, so `import oraclemesh_fc` and `import oraclemesh`
# both work in the GUI, in macros and in freecadcmd. Idempotent: re-running refreshes the links.
# Usage: cmake/install-workbench.sh BUILD_DIR   (FREECAD_USER_MOD_DIR overrides the Mod folder)
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 BUILD_DIR" >&2
  exit 2
fi
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(mkdir -p "$1" && cd "$1" && pwd)"
mods="${FREECAD_USER_MOD_DIR:-${XDG_DATA_HOME:-$HOME/.local/share}/FreeCAD/Mod}"
target="$mods/OracleMesh"

# An older install may have made Mod/OracleMesh itself a symlink: replace it by a directory.
if [ -L "$target" ]; then rm -f "$target"; fi
mkdir -p "$target"

link() {  # link SOURCE NAME: (re)make $target/NAME -> SOURCE, refusing to clobber real files
  local src="$1" dst="$target/$2"
  if [ -e "$dst" ] && [ ! -L "$dst" ]; then
    echo "install-workbench: $dst exists and is not a symlink; move it away first" >&2
    exit 1
  fi
  ln -sfn "$src" "$dst"
}

for item in "$repo"/Mod/OracleMesh/*; do
  name="$(basename "$item")"
  case "$name" in __pycache__) continue ;; esac
  link "$item" "$name"
done
link "$repo/icons" icons
# The core is staged by the build; the link may dangle until the first build finishes.
link "$build/python/oraclemesh" oraclemesh

# Drop links left by files that no longer exist in the repo (renamed or removed).
for dst in "$target"/*; do
  if [ -L "$dst" ] && [ ! -e "$dst" ] && [ "$(basename "$dst")" != oraclemesh ]; then
    rm -f "$dst"
  fi
done

if [ ! -e "$build/python/oraclemesh/__init__.py" ]; then
  echo "install-workbench: note: $build/python/oraclemesh is not built yet (the link is in place)" >&2
fi
echo "install-workbench: OracleMesh workbench linked into $target"
