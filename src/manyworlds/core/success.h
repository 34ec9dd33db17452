// The one success rule: an episode is a success if its env's `success` info
// field is above 0.5 at any step (Meta-World's and MTRL's rule; Meta-World's
// field is 0 or 1, as is every manyworlds env's). Rollouts, training,
// evaluation, the meta-test protocol and TerminateOnSuccess all ask here.
#ifndef MANYWORLDS_CORE_SUCCESS_H_
#define MANYWORLDS_CORE_SUCCESS_H_

namespace manyworlds {

inline constexpr float kSuccessThreshold = 0.5f;

// Whether one step's `success` info value counts as success.
inline bool IsSuccess(float success_field) { return success_field > kSuccessThreshold; }

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_SUCCESS_H_
