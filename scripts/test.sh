#!/usr/bin/env bash
# Installs dependencies, builds everything with tests (Release) and runs the
# whole test suite: the C++ tests (ctest), then the Python package's tests
# (scripts/python_test.sh: virtual environment .venv-py/, `pip install .`,
# pytest; its determinism test compares with the program built here), then
# 20 seconds of each libFuzzer target (scripts/fuzz.sh, clang + ASan/UBSan),
# then the C++ tests of the layers without libtorch built with ASan/UBSan
# (scripts/sanitize.sh, build-asan/). Idempotent; MANYWORLDS_BUILD_DIR picks
# another build directory (default build/). Exits non-zero if any suite
# fails; all always run.
#
# scripts/test.sh --quick: the edit-compile-test loop. The same build, then
# only the C++ tests not labelled slow (ctest -LE slow: the unit tests, the
# fast CLI and fidelity tests; no learning runs, no Python, fuzzing or
# sanitizer build). docs/contributing.md lists the labels.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${MANYWORLDS_BUILD_DIR:-build}
quick=0
for arg in "$@"; do
  case "$arg" in
    --quick) quick=1 ;;
    -h|--help)
      echo "usage: scripts/test.sh [--quick]  (--quick: only the C++ tests not labelled slow)"
      exit 0 ;;
    *) echo "test.sh: unknown argument '$arg'; allowed: --quick, --help" >&2; exit 2 ;;
  esac
done

stage_start=$SECONDS  # each stage's wall time is printed at the end
bash scripts/setup.sh
launcher=()
# ccache, where installed, makes the rebuilds of the edit-compile-test loop cheap
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DMANYWORLDS_BUILD_TESTS=ON "${launcher[@]}"
cmake --build "$build_dir" -j"$(nproc)"
if [ "$quick" -eq 1 ]; then
  exec ctest --test-dir "$build_dir" --output-on-failure -j2 -LE slow
fi
# each stage's wall time, printed at the end: CI's budget is 40 minutes on two cores
stage_times=()
stage_done() {
  stage_times+=("$(printf '%-34s %5d s' "$1" $((SECONDS - stage_start)))")
  stage_start=$SECONDS
}
stage_done "setup and C++ build"
cpp_status=0
# the failed-test lists named at the end are this run's
rm -f "$build_dir/Testing/Temporary/LastTestsFailed.log" build-asan/Testing/Temporary/LastTestsFailed.log
# CheckEnvPassesOnEveryRegisteredEnv (every env through the env checker, ~70 s) runs in the
# sanitizer build below, where it checks more; it is not run twice
case "$build_dir" in /*) junit=$build_dir/ctest-junit.xml ;; *) junit=$(pwd)/$build_dir/ctest-junit.xml ;; esac
ctest --test-dir "$build_dir" --output-on-failure -j2 --output-junit "$junit" \
  -E '^CliTest\.CheckEnvPassesOnEveryRegisteredEnv$' || cpp_status=$?
stage_done "C++ tests (ctest)"
case "$build_dir" in /*) cli=$build_dir/manyworlds ;; *) cli=$(pwd)/$build_dir/manyworlds ;; esac
py_status=0
# MANYWORLDS_NATIVE=ON: the Python extension is compiled as the main build is, so that ccache
# hands it the main build's objects (its env layers are not compiled a second time)
MANYWORLDS_CLI="$cli" MANYWORLDS_NATIVE=ON bash scripts/python_test.sh || py_status=$?
stage_done "Python package: build and pytest"
fuzz_status=0
bash scripts/fuzz.sh || fuzz_status=$?
stage_done "fuzzing (clang build and targets)"
sanitize_status=0
bash scripts/sanitize.sh || sanitize_status=$?
stage_done "sanitizer build and tests"
echo "test.sh: wall time per stage"
printf '  %s\n' "${stage_times[@]}"
printf '  %-34s %5d s\n' "total" "$SECONDS"
# the suite's budget is spent by its largest tests: CI's log ends with them
python3 scripts/slowest_tests.py "$junit" 15 || true
# CI shows the end of the log: name the failed tests here, not only thousands of lines above
for dir in "$build_dir" build-asan; do
  failed_list=$dir/Testing/Temporary/LastTestsFailed.log
  if [ -s "$failed_list" ]; then
    echo "test.sh: failed in $dir (ctest -R NAME --output-on-failure reruns one):"
    sed 's/^/  /' "$failed_list"
  fi
done
if [ "$cpp_status" -ne 0 ] || [ "$py_status" -ne 0 ] || [ "$fuzz_status" -ne 0 ] ||
   [ "$sanitize_status" -ne 0 ]; then
  echo "test.sh: C++ tests exit code $cpp_status, Python tests exit code $py_status," \
       "fuzzing exit code $fuzz_status, sanitizer build exit code $sanitize_status" >&2
  exit 1
fi
