#include "manyworlds/sim/warnings.h"

#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {
namespace {

const char* const kWarningNames[mjNWARNING] = {
    "INERTIA", "CONTACTFULL", "CNSTRFULL", "VGEOMFULL",
    "BADQPOS", "BADQVEL",     "BADQACC",   "BADCTRL"};

}  // namespace

int WarningTotal(const mjData* d) {
  int total = 0;
  for (int i = 0; i < mjNWARNING; ++i) total += d->warning[i].number;
  return total;
}

std::string DescribeWarnings(const mjData* d) {
  std::string text;
  for (int i = 0; i < mjNWARNING; ++i) {
    if (d->warning[i].number == 0) continue;
    if (!text.empty()) text += ", ";
    text += std::string(kWarningNames[i]) + " x" + std::to_string(d->warning[i].number) +
            " (info " + std::to_string(d->warning[i].lastinfo) + ")";
  }
  return text;
}

void ClearWarnings(mjData* d) {
  for (int i = 0; i < mjNWARNING; ++i) {
    d->warning[i].number = 0;
    d->warning[i].lastinfo = 0;
  }
}

void ThrowIfWarnings(const mjData* d, std::string_view context) {
  if (WarningTotal(d) == 0) return;
  throw SimulationWarningError(std::string(context) + ": MuJoCo warnings: " + DescribeWarnings(d));
}

int StepAndCheck(const mjModel* m, mjData* d, int substeps, bool throw_on_warning,
                 std::string_view context) {
  const int before = WarningTotal(d);
  for (int i = 0; i < substeps; ++i) mj_step(m, d);
  const int raised = WarningTotal(d) - before;
  if (raised > 0 && throw_on_warning) ThrowIfWarnings(d, context);
  return raised;
}

}  // namespace manyworlds::sim
