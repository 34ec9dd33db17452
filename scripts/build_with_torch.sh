#!/usr/bin/env bash
# Builds manyworlds against the libtorch inside a Python environment's `torch` package (PyPI's
# wheels, CPU or CUDA builds, torch >= 2.7 for the C++11 ABI that Debian's libraries use)
# instead of Debian's libtorch 1.13. The other dependencies stay Debian's (scripts/setup.sh).
#
#   scripts/build_with_torch.sh --python .venv-torch/bin/python            # build-torch/, Release
#   scripts/build_with_torch.sh --python PY --build-dir DIR --tests         # and the C++ tests
#   scripts/build_with_torch.sh --python PY --configure-only                 # CMake's step only
#   ctest --test-dir build-torch -LE slow -j2                                # then run them
#
# What it settles for a wheel's libtorch (docs/usage.md#building-against-another-libtorch):
#  - CMAKE_PREFIX_PATH: torch.utils.cmake_prefix_path;
#  - the wheel's ABI must be the C++11 one (torch._C._GLIBCXX_USE_CXX11_ABI), else one error line;
#  - CUDA wheels: TORCH_CUDA_ARCH_LIST from the wheel's own architectures, so that torch's CMake
#    does not try to detect a GPU (which fails without one, and with CMake 3.25's nvcc dialects);
#    -rpath-link to the wheel's nvidia/*/lib folders, so that the linker resolves libtorch_cuda's
#    NCCL, cuDNN and CUDA libraries from the wheel and not from a CUDA toolkit elsewhere.
set -euo pipefail
cd "$(dirname "$0")/.."
python=python3
build_dir=build-torch
tests=OFF
configure_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --python) python=${2:?--python needs a path}; shift 2 ;;
    --build-dir) build_dir=${2:?--build-dir needs a path}; shift 2 ;;
    --tests) tests=ON; shift ;;
    --configure-only) configure_only=1; shift ;;
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "build_with_torch.sh: unknown argument '$1'; allowed: --python PY, --build-dir DIR, --tests, --configure-only, --help" >&2
       exit 2 ;;
  esac
done
facts=$("$python" - <<'EOF' 2>/dev/null
import os
import torch
site = os.path.dirname(os.path.dirname(torch.__file__))
arch = ";".join(f"{a[3:-1]}.{a[-1]}" for a in torch.cuda.get_arch_list() if a.startswith("sm_"))
print(torch.__version__)
print(torch.utils.cmake_prefix_path)
print(int(torch._C._GLIBCXX_USE_CXX11_ABI))
print(torch.version.cuda or "")
print(arch)
print(os.path.join(site, "nvidia"))
EOF
) || { echo "build_with_torch.sh: '$python' cannot import torch; give a Python with torch installed (--python)" >&2; exit 2; }
{ read -r version; read -r prefix; read -r cxx11; read -r cuda; read -r arch_list; read -r nvidia; } <<< "$facts"
if [ "$cxx11" != 1 ]; then
  echo "build_with_torch.sh: torch $version was built with the pre-C++11 ABI, which Debian's libraries do not use; install torch >= 2.7" >&2
  exit 2
fi
link_flags=""
if [ -d "$nvidia" ]; then
  for dir in "$nvidia"/*/lib; do [ -d "$dir" ] && link_flags+=" -Wl,-rpath-link,$dir"; done
fi
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
echo "build_with_torch.sh: torch $version${cuda:+ (CUDA $cuda)} from $prefix, into $build_dir/"
TORCH_CUDA_ARCH_LIST=${TORCH_CUDA_ARCH_LIST:-${arch_list:-9.0}} \
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DMANYWORLDS_BUILD_TESTS="$tests" \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_EXE_LINKER_FLAGS="$link_flags" \
    -DCMAKE_SHARED_LINKER_FLAGS="$link_flags" "${launcher[@]}"
[ "$configure_only" -eq 0 ] || exit 0
cmake --build "$build_dir" -j"$(nproc)"
echo "build_with_torch.sh: built $build_dir/manyworlds against torch $version"
