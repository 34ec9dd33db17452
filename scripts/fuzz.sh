#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang, ASan and UBSan in build-fuzz/
# and runs each one on its seed corpus (tests/fuzz/corpus/TARGET/).
#
#   scripts/fuzz.sh                           # 20 seconds per target, seed 1 (CI)
#   scripts/fuzz.sh --runs 1000000            # 10^6 inputs per target (docs/reliability.md)
#   scripts/fuzz.sh --runs 1000000 checkpoint # only the named targets
#
# New inputs found go to build-fuzz/corpus/TARGET/ (the seeds stay as they
# are); a crash or a hang (an input running over 30 s) leaves
# build-fuzz/crash-* or timeout-* and exits non-zero. Needs clang (Debian:
# clang), which setup.sh does not install; installed here if missing.
# MANYWORLDS_JOBS sets the build's parallel jobs (default: every core).
set -euo pipefail
cd "$(dirname "$0")/.."
budget=(-max_total_time=20 -seed=1)
if [ "${1:-}" = "--runs" ]; then
  budget=(-runs="${2:?--runs needs a count}")
  shift 2
fi

if ! command -v clang++ > /dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update && $SUDO apt-get install -y --no-install-recommends clang
fi
bash scripts/setup.sh
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# Only the layers the parsers live in: core, config, classic, and sim,
# manipulation, locomotion, boxworld on the (uninstrumented) MuJoCo library. No torch
# layer: the checkpoint and replay readers have no libtorch and are compiled
# into their targets (see fuzz/CMakeLists.txt).
# -O1: the build is faster than at -O2, and 20 s of fuzzing needs no more speed
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DMANYWORLDS_FUZZ=ON -DMANYWORLDS_WITH_TORCH=OFF -DMANYWORLDS_BUILD_TESTS=OFF \
  -DMANYWORLDS_BUILD_BENCHMARKS=OFF -DMANYWORLDS_NATIVE=OFF -DCMAKE_DISABLE_FIND_PACKAGE_mujoco=OFF \
  > build-fuzz.log
# every target this build defines (fuzz_task_state_mujoco needs MuJoCo), or
# the ones named on the command line
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  defined=$(cmake --build build-fuzz --target help)
  for target in yaml override task_state task_state_mujoco checkpoint replay; do
    if grep -qx "\.\.\. fuzz_$target" <<< "$defined"; then targets+=("$target"); fi
  done
fi
cmake --build build-fuzz -j "${MANYWORLDS_JOBS:-$(nproc)}" --target "${targets[@]/#/fuzz_}" \
  >> build-fuzz.log
status=0
for target in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$target"
  echo "fuzz_$target: ${budget[*]}"
  dict=()  # fuzz/TARGET.dict: the words of the format, if any
  if [ -f "fuzz/$target.dict" ]; then dict=(-dict="../fuzz/$target.dict"); fi
  (cd build-fuzz && "./fuzz/fuzz_$target" "${budget[@]}" "${dict[@]}" -max_len=4096 -timeout=30 \
      -print_final_stats=1 "corpus/$target" "../tests/fuzz/corpus/$target" > "fuzz_$target.log" 2>&1) \
    || status=$?
  tail -n 12 "build-fuzz/fuzz_$target.log"
done
exit "$status"
