"""manyworlds beside other native libraries in one process.

The extension must not push its dependencies into the process's global symbol scope: Mesa's
libOSMesa (the offscreen renderer) depends on libLLVM, and once that was global, Triton (which
PyTorch 2 imports when an optimizer is made) bound its own LLVM's static initialisers to it
and crashed the interpreter. Only the dependency-free shim that defines OSMesaGetProcAddress
(for MuJoCo's GL loader) may be global. Each check runs in a fresh interpreter.
"""

import subprocess
import sys
import textwrap

import pytest

import manyworlds


def run_python(code):
    result = subprocess.run([sys.executable, "-c", textwrap.dedent(code)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, f"exit code {result.returncode}\n{result.stdout}\n{result.stderr}"
    return result.stdout


def test_import_leaves_llvm_and_osmesa_out_of_the_global_scope():
    out = run_python("""
        import ctypes
        import manyworlds
        maps = open("/proc/self/maps").read()
        g = ctypes.CDLL(None)  # dlsym on this handle searches the global scope
        print("llvm_loaded", "libLLVM" in maps)
        print("llvm_global", hasattr(g, "LLVMContextCreate"))
        print("osmesa_global", hasattr(g, "OSMesaCreateContextExt"))
        print("shim_global", hasattr(g, "OSMesaGetProcAddress"))
    """)
    flags = dict(line.split() for line in out.splitlines())
    assert flags["llvm_global"] == "False"
    assert flags["osmesa_global"] == "False"
    if manyworlds._core.has_render:
        assert flags["shim_global"] == "True"


@pytest.mark.skipif(not (manyworlds._core.has_render and manyworlds._core.has_mujoco),
                    reason="this build has no renderer")
def test_render_works_with_only_the_shim_global():
    out = run_python("""
        import manyworlds
        env = manyworlds.make("reach", render_mode="rgb_array", width=32, height=32)
        env.reset(seed=0)
        frame = env.render()
        print(frame.shape, int(frame.max()) > 0)
    """)
    assert out.strip() == "(32, 32, 3) True"
