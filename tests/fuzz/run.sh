#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/CMakeLists.txt, clang) and runs each for SECONDS
# (default 10) on its corpus in tests/fuzz/corpus/<target>/. Fails when a target crashes,
# leaks, trips a sanitizer or lets an exception other than InputError escape; the input
# that did it is left in the build folder (crash-*, printed). Add it to the target's corpus
# (a regression input) once it is fixed. The brep, step and iges targets run OpenCASCADE in the
# helper oraclemesh-shape-reader built beside them: its crashes and hangs are contained (an
# InputError), only the fuzzer's own process can fail. A seed on which OpenCASCADE hangs costs
# the target's time limit (3 s) each run, so those targets start more slowly than the others.
#   bash tests/fuzz/run.sh            every target briefly (tests/run.sh: 6 s each)
#   bash tests/fuzz/run.sh 600 nrrd   a long run of one target (brep, step, iges, job, stl, ...)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
seconds="${1:-10}"
only="${2:-}"
build="${ORACLEMESH_FUZZ_BUILD_DIR:-${ORACLEMESH_BUILD_DIR:-$here/../../build}/fuzz}"

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ >/dev/null
# One build at a time on a shared machine (see the README's build notes).
if [ -e /tmp/oraclemesh-build.lock ]; then
  flock /tmp/oraclemesh-build.lock cmake --build "$build" -j2
else
  cmake --build "$build" -j2
fi

status=0
for corpus in "$here"/corpus/*/; do
  target="$(basename "$corpus")"
  [ -z "$only" ] || [ "$only" = "$target" ] || continue
  fresh="$(mktemp -d)"  # new inputs found go here, not into the repository
  # IGES spends 80 columns a line on little: the seed from the shared models' screw.step is 84 KB.
  max_len=65536
  [ "$target" != iges ] || max_len=131072
  # -rss_limit_mb: a reader must not allocate gigabytes for a small file; -timeout: nor hang.
  if "$build/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
      -artifact_prefix="$build/$target-" -print_final_stats=0 "$fresh" "$corpus" >"$build/$target.log" 2>&1; then
    echo "fuzz $target: ok ($(grep -c . <(ls "$corpus")) corpus inputs, $(ls "$fresh" | wc -l) new, ${seconds} s)"
  else
    status=1
    echo "fuzz $target: FAILED, see $build/$target.log" >&2
    grep -E "ERROR|SUMMARY|Test unit written|uncaught|deadly" "$build/$target.log" | head -20 >&2
  fi
  rm -rf "$fresh"
done
exit $status
