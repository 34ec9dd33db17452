// Simulation warnings. MuJoCo 2.2.2 does not fail a step that goes wrong: it
// counts the event in mjData::warning[i].number (and for a bad qacc resets
// the data itself). These helpers turn the counters into reportable events.
#ifndef MANYWORLDS_SIM_WARNINGS_H_
#define MANYWORLDS_SIM_WARNINGS_H_

#include <string>
#include <string_view>

#include <mujoco/mujoco.h>

namespace manyworlds::sim {

// Total of all warning counters (cheap: mjNWARNING ints).
int WarningTotal(const mjData* data);

// "BADQACC x2 (info 14), CONTACTFULL x1 (info 100)", or "" if none.
std::string DescribeWarnings(const mjData* data);

// Zeroes the counters (mj_resetData also does).
void ClearWarnings(mjData* data);

// Throws SimulationWarningError ("<context>: MuJoCo warnings: ...") if any
// counter is non-zero.
void ThrowIfWarnings(const mjData* data, std::string_view context);

// mj_step `substeps` times, then ThrowIfWarnings if `throw_on_warning`.
// Returns the number of new warnings raised by these steps.
int StepAndCheck(const mjModel* model, mjData* data, int substeps, bool throw_on_warning,
                 std::string_view context = "step");

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_WARNINGS_H_
