#!/usr/bin/env bash
# install_test.sh BUILD_DIR EXAMPLE_DIR [MUJOCO_DIR]
# cmake --install into a fresh prefix, then configure, build and run the
# example with only that prefix on CMAKE_PREFIX_PATH.
set -euo pipefail
build_dir=$1
example_dir=$2
mujoco_dir=${3:-}
work=$(mktemp -d "${TMPDIR:-/tmp}/manyworlds_install_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

# quiet on success, the whole log on failure
step() {
  local name=$1
  shift
  if ! "$@" > "$work/$name.log" 2>&1; then
    echo "install test: '$name' failed:" >&2
    cat "$work/$name.log" >&2
    exit 1
  fi
}

step install cmake --install "$build_dir" --prefix "$work/prefix"
extra=()
# the consumer must see the same MuJoCo package as the build did
if [ -n "$mujoco_dir" ] && [ "$mujoco_dir" != "mujoco_DIR-NOTFOUND" ]; then
  extra+=("-Dmujoco_DIR=$mujoco_dir")
fi
step configure cmake -S "$example_dir" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release "${extra[@]}"
step build cmake --build "$work/build" -j2
"$work/build/gym_loop"
