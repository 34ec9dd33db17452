// Makes OpenBLAS run the kernels of this CPU.
//
// Debian 12's OpenBLAS (0.3.21, DYNAMIC_ARCH) chooses its kernels once, when
// it loads, from the CPU model; models newer than it knows (e.g. Intel
// family 6 model 207, Emerald Rapids) get its generic SSE3 "Prescott"
// kernels, which ran SAC updates 3x slower than its AVX-512 kernels on such
// a machine (docs/benchmarks.md). OpenBLAS honours OPENBLAS_CORETYPE, but
// reads it only while it loads, before any code of ours runs. So this
// constructor, which runs after every shared library's initialiser, looks at
// the kernels OpenBLAS chose and, when they are a generic fallback on a CPU
// with AVX2 or AVX-512 and the user has not set OPENBLAS_CORETYPE, selects
// them again with OPENBLAS_CORETYPE set from the CPU's instruction sets:
// through OpenBLAS's exported gotoblas_dynamic_quit/gotoblas_dynamic_init
// (no BLAS call can be running this early), or, where those are missing,
// by executing the program again with the variable set. Elsewhere it does
// nothing. The nn layer adds this file to every executable built in this
// project that links it.
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace {

const char* CoreTypeForThisCpu() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq")) {
    return "OPENBLAS_CORETYPE=SkylakeX";
  }
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    return "OPENBLAS_CORETYPE=Haswell";
  }
  return nullptr;
}

bool IsGenericCore(const char* core) {
  for (const char* generic : {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem", "Atom",
                              "Unknown"}) {
    if (std::strcmp(core, generic) == 0) return true;
  }
  return false;
}

bool Reselect(const char* setting) {
  using Hook = void (*)();
  auto quit = reinterpret_cast<Hook>(dlsym(RTLD_DEFAULT, "gotoblas_dynamic_quit"));
  auto init = reinterpret_cast<Hook>(dlsym(RTLD_DEFAULT, "gotoblas_dynamic_init"));
  if (quit == nullptr || init == nullptr) return false;
  const char* value = std::strchr(setting, '=') + 1;
  if (setenv("OPENBLAS_CORETYPE", value, /*overwrite=*/1) != 0) return false;
  quit();
  init();  // reads OPENBLAS_CORETYPE and runs the chosen kernels' set-up
  unsetenv("OPENBLAS_CORETYPE");  // leave the user's environment as it was
  return true;
}

__attribute__((constructor)) void RunOnTheKernelsOfThisCpu(int, char** argv, char** envp) {
  if (argv == nullptr || envp == nullptr || std::getenv("OPENBLAS_CORETYPE") != nullptr) return;
  auto corename = reinterpret_cast<char* (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (corename == nullptr || !IsGenericCore(corename())) return;
  const char* setting = CoreTypeForThisCpu();
  if (setting == nullptr) return;
  if (Reselect(setting) && !IsGenericCore(corename())) return;
  int n = 0;
  while (envp[n] != nullptr) ++n;
  char** env = static_cast<char**>(std::malloc(sizeof(char*) * static_cast<size_t>(n + 2)));
  if (env == nullptr) return;
  std::memcpy(env, envp, sizeof(char*) * static_cast<size_t>(n));
  env[n] = const_cast<char*>(setting);
  env[n + 1] = nullptr;
  // exec the binary by its own path, not /proc/self/exe, so that ps and
  // pgrep still show the program's name
  char path[4096];
  const ssize_t length = readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (length > 0) {
    path[length] = '\0';
    execve(path, argv, env);
  }
  std::free(env);  // exec failed (no /proc): carry on with the kernels we have
}

}  // namespace
