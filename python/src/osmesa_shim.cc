// libmanyworlds_osmesa_shim.so: the one OSMesa symbol MuJoCo 2.2.2 looks up
// in the global symbol scope, and nothing else.
//
// MuJoCo's GL loader finds OSMesaGetProcAddress with dlsym in the global
// scope, but Python opens extension modules (and so the libOSMesa that
// manyworlds._core links) with RTLD_LOCAL. Promoting libOSMesa itself to the
// global scope would also make its dependencies global, among them Mesa's
// libLLVM-15: every library loaded afterwards that carries its own copy of
// LLVM (Triton, which PyTorch 2 imports when an optimizer is made) would then
// bind its LLVM calls to Mesa's and crash at load. This library has no
// dependencies; manyworlds._core opens it with RTLD_GLOBAL and hands it the
// real OSMesaGetProcAddress (module.cc), so only this symbol becomes global.
// Plain C ABI, no C++ runtime, so that no C++ library becomes global either.

using ProcAddressFn = void* (*)(const char*);

namespace {
ProcAddressFn g_real = nullptr;
}  // namespace

extern "C" {

__attribute__((visibility("default"))) void manyworlds_osmesa_shim_set(ProcAddressFn real) {
  g_real = real;
}

__attribute__((visibility("default"))) void* OSMesaGetProcAddress(const char* name) {
  return g_real != nullptr ? g_real(name) : nullptr;
}

}  // extern "C"
