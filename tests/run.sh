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
# Two streams, one core each: pytest (its FreeCAD presse test alone is a quarter of an hour) and
# ctest followed by the fuzz targets, which ran after both and left a core idle for the end of
# pytest. The checks labelled "long" (tens of minutes) belong to the benchmarks: ctest -L long.
# The fuzz step builds the parsers, readers and B-rep loading with clang and runs each under
# libFuzzer for 6 s (a long run of one target: bash tests/fuzz/run.sh 600 nrrd).
ctest_log="$ORACLEMESH_TEST_OUTPUT/ctest.log"
fuzz_log="$ORACLEMESH_TEST_OUTPUT/fuzz.log"
(
  stream=0
  ctest --test-dir "$build" --output-on-failure -LE long -j1 >"$ctest_log" 2>&1 || stream=1
  bash tests/fuzz/run.sh 6 >"$fuzz_log" 2>&1 || stream=1
  exit $stream
) &
second_stream=$!
PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m pytest -p no:cacheprovider \
  -v --durations=15 tests/python tests/freecad || status=1
wait "$second_stream" || status=1
cat "$ctest_log"
cat "$fuzz_log"
echo "tests/run.sh: build + tests took $(( $(date +%s) - start )) s"
exit $status
