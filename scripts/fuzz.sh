#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) in the clang ASan/UBSan build they share
# with the sanitizer tests (scripts/asan_build.sh, build-asan/) and runs each
# one on its seed corpus (tests/fuzz/corpus/TARGET/), as many at a time as
# there are cores.
#
#   scripts/fuzz.sh                           # 20 seconds per target, seed 1 (CI)
#   scripts/fuzz.sh --runs 1000000            # 10^6 inputs per target (docs/reliability.md)
#   scripts/fuzz.sh --runs 1000000 checkpoint # only the named targets
#
# New inputs found go to build-asan/corpus/TARGET/ (the seeds stay as they
# are); a crash or a hang (an input running over 30 s) leaves
# build-asan/crash-* or timeout-* and exits non-zero. Each target's output is
# build-asan/fuzz_TARGET.log, whose last lines are printed.
# MANYWORLDS_JOBS sets the build's jobs and how many targets run at once
# (default: every core).
set -euo pipefail
cd "$(dirname "$0")/.."
budget=(-max_total_time=20 -seed=1)
if [ "${1:-}" = "--runs" ]; then
  budget=(-runs="${2:?--runs needs a count}")
  shift 2
fi
jobs=${MANYWORLDS_JOBS:-$(nproc)}

# every target this build defines (fuzz_task_state_mujoco needs MuJoCo), or
# the ones named on the command line
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  bash scripts/asan_build.sh --configure-only
  defined=$(cmake --build build-asan --target help)
  for target in yaml override registry_option task_state task_state_mujoco checkpoint replay; do
    if grep -qx "\.\.\. fuzz_$target" <<< "$defined"; then targets+=("$target"); fi
  done
fi
bash scripts/asan_build.sh "${targets[@]/#/fuzz_}"

run_target() {
  local target=$1 dict=()  # fuzz/TARGET.dict: the words of the format, if any
  mkdir -p "build-asan/corpus/$target"
  if [ -f "fuzz/$target.dict" ]; then dict=(-dict="../fuzz/$target.dict"); fi
  (cd build-asan && "./fuzz/fuzz_$target" "${budget[@]}" "${dict[@]}" -max_len=4096 -timeout=30 \
      -print_final_stats=1 "corpus/$target" "../tests/fuzz/corpus/$target" > "fuzz_$target.log" 2>&1)
}
status=0
pids=()
for target in "${targets[@]}"; do
  # at most $jobs targets at once: wait for the oldest before starting another
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=$?
    pids=("${pids[@]:1}")
  fi
  echo "fuzz_$target: ${budget[*]}"
  run_target "$target" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid" || status=$?; done
for target in "${targets[@]}"; do
  echo "== fuzz_$target"
  tail -n 12 "build-asan/fuzz_$target.log"
done
exit "$status"
