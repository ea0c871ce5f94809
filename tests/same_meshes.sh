#!/usr/bin/env bash
# A refactor must change no mesh: meshes this tree's CLI makes are compared byte for byte with
# those of BASE_REV's CLI, on the same job files.
#   tests/same_meshes.sh [BASE_REV]        (default 70c6bc4, the commit before the "rooms" split)
# Jobs: the demo assembly (built by BASE_REV's workbench code in freecadcmd, tet10), the
# implant_in_bone example (row (a): thesis engine with sharp edges and junctions) and part.step
# with sharp edges at default sizes (tet10).
# Environment: ORACLEMESH_BUILD_DIR (this tree's build, default build/), ORACLEMESH_BASE_DIR
# (where BASE_REV is unpacked and built, default /tmp/oraclemesh-base-REV; kept for reruns),
# ORACLEMESH_CAD_DIR (default ../shared/data/cad).
# Exit 0 when every mesh is identical, 1 when one differs, 2 when a job fails.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rev="${1:-70c6bc4}"
build="${ORACLEMESH_BUILD_DIR:-$repo/build}"
cad="$(cd "${ORACLEMESH_CAD_DIR:-$repo/../shared/data/cad}" && pwd)"
sha="$(git -C "$repo" rev-parse --short "$rev^{commit}")"
base="${ORACLEMESH_BASE_DIR:-/tmp/oraclemesh-base-$sha}"
work="$(mktemp -d /tmp/oraclemesh-same-meshes.XXXXXX)"
trap 'rm -rf "$work"' EXIT

build_cli() {  # build_cli SOURCE_DIR BUILD_DIR
  [ -f "$2/build.ninja" ] || cmake -S "$1" -B "$2" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DORACLEMESH_BUILD_TESTS=OFF -DORACLEMESH_BUILD_PYTHON=OFF >/dev/null
  cmake --build "$2" -j2 --target oraclemesh_cli >/dev/null
}

if [ ! -f "$base/CMakeLists.txt" ]; then
  mkdir -p "$base"
  git -C "$repo" archive "$sha" | tar -x -C "$base"
fi
echo "same_meshes: building $sha in $base/build and this tree in $build"
build_cli "$base" "$base/build"
build_cli "$repo" "$build"

# The job files, made once by BASE_REV's own scripts so both CLIs read the same bytes.
jobs="$work/jobs"
mkdir -p "$jobs/implant"
/usr/bin/python3 "$base/examples/implant_in_bone/make_implant_in_bone.py" "$jobs/implant" >/dev/null
cp "$base/examples/implant_in_bone/implant_in_bone.json" "$jobs/implant/implant.json"
cat >"$jobs/part.json" <<JSON
{"inputs": [{"name": "part", "file": "$cad/part.step"}], "element_order": 2, "seed": 0}
JSON
cat >"$work/demo_job.py" <<'PY'
import json, os, sys
sys.path.insert(0, os.path.join(os.environ["BASE"], "Mod", "OracleMesh"))
import FreeCAD
from oraclemesh_fc import demo, job, makeMesh
doc = FreeCAD.newDocument("SameMeshes")
analysis, solver, pin, plate, corner = demo.build(doc)
mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner],
                cell_size=4.0, facet_distance=0.1, element_order=2)
with open(os.environ["OUT"], "w") as f:
    json.dump(job.build_job(mesh)[0], f)
PY
BASE="$base" OUT="$jobs/demo.json" freecadcmd "$work/demo_job.py" >"$work/demo_job.log" 2>&1 || true
[ -s "$jobs/demo.json" ] || { cat "$work/demo_job.log" >&2; echo "same_meshes: could not write the demo job" >&2; exit 2; }

run() {  # run CLI JOB OUT.vtu: the job with its output set to OUT.vtu only
  local job="$work/$(basename "$3" .vtu).json"
  /usr/bin/python3 - "$2" "$3" "$job" <<'PY'
import json, sys
job = json.load(open(sys.argv[1]))
job["output"] = {"files": [sys.argv[2]]}
json.dump(job, open(sys.argv[3], "w"))
PY
  # Relative input paths in a job are relative to its folder: run it from the original's.
  cp "$job" "$(dirname "$2")/.same_meshes_$(basename "$job")"
  "$1" "$(dirname "$2")/.same_meshes_$(basename "$job")" >"$work/$(basename "$3" .vtu).log" 2>&1 || {
    tail -5 "$work/$(basename "$3" .vtu).log" >&2
    echo "same_meshes: $(basename "$2") failed with $1" >&2
    exit 2
  }
}

status=0
for name in demo implant part; do
  case "$name" in
    demo) job="$jobs/demo.json" ;;
    implant) job="$jobs/implant/implant.json" ;;
    part) job="$jobs/part.json" ;;
  esac
  run "$base/build/oraclemesh" "$job" "$work/$name-base.vtu"
  run "$build/oraclemesh" "$job" "$work/$name-this.vtu"
  if cmp -s "$work/$name-base.vtu" "$work/$name-this.vtu"; then
    echo "same_meshes: $name identical ($(stat -c %s "$work/$name-this.vtu") bytes)"
  else
    echo "same_meshes: $name DIFFERS from $sha ($(stat -c %s "$work/$name-base.vtu") vs $(stat -c %s "$work/$name-this.vtu") bytes)"
    status=1
  fi
done
exit $status
