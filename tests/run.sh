#!/usr/bin/env bash
# The README's test command: installs what is missing, builds from scratch, runs every test
# (C++ unit and pipeline tests via ctest, Python and FreeCAD/CalculiX tests via pytest).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build="${ORACLEMESH_BUILD_DIR:-$repo/build}"
export ORACLEMESH_BUILD_DIR="$build"
export ORACLEMESH_CAD_DIR="${ORACLEMESH_CAD_DIR:-$repo/../shared/data/cad}"
export ORACLEMESH_TEST_OUTPUT="${ORACLEMESH_TEST_OUTPUT:-$repo/tests/output}"

start=$(date +%s)
bash cmake/install-deps.sh
rm -rf "$build" "$ORACLEMESH_TEST_OUTPUT"
mkdir -p "$ORACLEMESH_TEST_OUTPUT"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DORACLEMESH_CAD_DIR="$ORACLEMESH_CAD_DIR"
# -j2: the machine has two cores and the CGAL translation units need ~3 GiB each.
cmake --build "$build" -j2
bash cmake/install-workbench.sh "$build"
built=$(date +%s)
echo "tests/run.sh: clean build took $((built - start)) s"

status=0
# ctest and pytest side by side, one core each: the FreeCAD tests are mostly one busy
# process, so running them after ctest left a core idle for half the run. The checks
# labelled "long" (tens of minutes) belong to the benchmarks: ctest -L long.
ctest_log="$ORACLEMESH_TEST_OUTPUT/ctest.log"
ctest --test-dir "$build" --output-on-failure -LE long -j1 >"$ctest_log" 2>&1 &
ctest_pid=$!
PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m pytest -p no:cacheprovider \
  -v --durations=15 tests/python tests/freecad || status=1
wait "$ctest_pid" || status=1
cat "$ctest_log"
# The parsers, readers and B-rep loading under libFuzzer, briefly, 6 s a target (its own small clang
# build; a long run of one target: bash tests/fuzz/run.sh 600 nrrd).
bash tests/fuzz/run.sh 6 || status=1
echo "tests/run.sh: build + tests took $(( $(date +%s) - start )) s"
exit $status
