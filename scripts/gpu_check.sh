#!/usr/bin/env bash
# The GPU machine's check: builds manyworlds against that machine's PyTorch (its libtorch, CUDA)
# with our Debian libraries unpacked from .debs/ (scripts/gpu_debs.sh fetches them beforehand
# where Debian's archive is reachable; the GPU machine has CUDA, PyTorch, CMake and a compiler,
# but none of our packages and no network), then runs the C++ tests not labelled slow and writes
# everything to a log. What it checks today: that the project builds and passes its tests against
# a CUDA libtorch on that machine, and what the machine is; the learners do not use the GPU yet
# (agent.device is not built), so there are no tests labelled gpu to run.
#
#   scripts/gpu_debs.sh                                   # here, once: .debs/ (about 4.5 MB)
#   scripts/gpu_check.sh [--python PY] [--configure-only] [--log FILE]   # there
#
# --python: the Python that holds torch (default python3); --configure-only: unpack and
# configure, no build (seconds; checks that every package resolves from .debs/); --log: the log
# (default $OUT/gpu_check.log when $OUT is set, else build-gpu/gpu_check.log). Build directory:
# build-gpu/. Prefix of the unpacked packages: $MANYWORLDS_DEB_PREFIX (default /tmp/manyworlds-debs).
set -euo pipefail
cd "$(dirname "$0")/.."
python=python3
configure_only=0
log=""
while [ $# -gt 0 ]; do
  case "$1" in
    --python) python=${2:?--python needs a path}; shift 2 ;;
    --configure-only) configure_only=1; shift ;;
    --log) log=${2:?--log needs a file}; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu_check.sh: unknown argument '$1'; allowed: --python PY, --configure-only, --log FILE, --help" >&2
       exit 2 ;;
  esac
done
debs=(.debs/*.deb)
if [ ! -e "${debs[0]}" ]; then
  echo "gpu_check.sh: no .debs/*.deb; run scripts/gpu_debs.sh where Debian's archive is reachable and bring .debs/ along" >&2
  exit 2
fi
build_dir=build-gpu
mkdir -p "$build_dir"
[ -n "$log" ] || log=${OUT:+$OUT/gpu_check.log}
[ -n "$log" ] || log=$build_dir/gpu_check.log
exec > >(tee "$log") 2>&1
start=$SECONDS
echo "# gpu_check.sh, $(date -u +%Y-%m-%dT%H:%M:%SZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo "# $(nproc) CPUs; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null |
  sed 's/^/# GPU: /' || echo "# GPU: nvidia-smi not found"
"$python" -c 'import torch; print("# torch", torch.__version__, "CUDA", torch.version.cuda,
    "available", torch.cuda.is_available())' || { echo "gpu_check.sh: '$python' cannot import torch" >&2; exit 2; }

# Debian's packages into a prefix of their own (unpacking into / can break the machine's own)
prefix=${MANYWORLDS_DEB_PREFIX:-/tmp/manyworlds-debs}
mkdir -p "$prefix"
for deb in "${debs[@]}"; do
  if command -v dpkg-deb > /dev/null; then
    dpkg-deb -x "$deb" "$prefix"
  else  # a .deb is an ar archive holding data.tar.*
    (tmp=$(mktemp -d) && cd "$tmp" && ar x "$OLDPWD/$deb" && tar -xf data.tar.* -C "$prefix" && rm -rf "$tmp")
  fi
done
libdir=$prefix/usr/lib/x86_64-linux-gnu
export CMAKE_PREFIX_PATH="$prefix/usr${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
echo "# ${#debs[@]} packages unpacked in $prefix"

if [ "$configure_only" -eq 1 ]; then
  scripts/build_with_torch.sh --python "$python" --build-dir "$build_dir" --tests --configure-only \
    > "$build_dir/configure.log" 2>&1 ||
    { tail -20 "$build_dir/configure.log"; echo "gpu_check.sh: configure failed" >&2; exit 1; }
  for package in mujoco yaml-cpp CLI11 nlohmann_json GTest Torch; do
    echo "# $package: $(grep -m1 "^${package}_DIR:" "$build_dir/CMakeCache.txt" | cut -d= -f2)"
  done
  echo "gpu_check.sh: configured in $((SECONDS - start)) s (--configure-only)"
  exit 0
fi
scripts/build_with_torch.sh --python "$python" --build-dir "$build_dir" --tests
echo "# built in $((SECONDS - start)) s"
status=0
ctest --test-dir "$build_dir" -LE slow -j"$(nproc)" --output-on-failure || status=$?
echo "gpu_check.sh: ctest exit code $status after $((SECONDS - start)) s; log: $log"
exit "$status"
