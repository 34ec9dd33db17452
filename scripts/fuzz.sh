#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang, ASan and UBSan in build-fuzz/
# and runs each one on its seed corpus (tests/fuzz/corpus/TARGET/).
#
#   scripts/fuzz.sh                 # 20 seconds per target, seed 1 (CI)
#   scripts/fuzz.sh --runs 1000000  # 10^6 inputs per target (docs/reliability.md)
#
# New inputs found go to build-fuzz/corpus/TARGET/ (the seeds stay as they
# are); a crash leaves build-fuzz/crash-* and exits non-zero. Needs clang
# (Debian: clang), which setup.sh does not install; installed here if missing.
set -euo pipefail
cd "$(dirname "$0")/.."
budget=(-max_total_time=20 -seed=1)
if [ "${1:-}" = "--runs" ]; then budget=(-runs="${2:?--runs needs a count}"); fi

if ! command -v clang++ > /dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update && $SUDO apt-get install -y --no-install-recommends clang
fi
bash scripts/setup.sh
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# only the layers the parsers live in: no libtorch, no MuJoCo
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DMANYWORLDS_FUZZ=ON -DMANYWORLDS_WITH_TORCH=OFF -DMANYWORLDS_BUILD_TESTS=OFF \
  -DMANYWORLDS_BUILD_BENCHMARKS=OFF -DMANYWORLDS_NATIVE=OFF -DCMAKE_DISABLE_FIND_PACKAGE_mujoco=ON \
  > build-fuzz.log
cmake --build build-fuzz -j "$(nproc)" --target fuzz_yaml fuzz_override fuzz_task_state >> build-fuzz.log
for target in yaml override task_state; do
  mkdir -p "build-fuzz/corpus/$target"
  echo "fuzz_$target: ${budget[*]}"
  (cd build-fuzz && "./fuzz/fuzz_$target" "${budget[@]}" -max_len=4096 -print_final_stats=1 \
      "corpus/$target" "../tests/fuzz/corpus/$target" 2>&1 | tail -n 12)
done
