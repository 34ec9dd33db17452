// Exception types raised by manyworlds. Every message names the object that
// failed (env id, option, file) and says what would have been allowed.
#ifndef MANYWORLDS_CORE_ERROR_H_
#define MANYWORLDS_CORE_ERROR_H_

#include <stdexcept>
#include <string>

namespace manyworlds {

// Base of every error manyworlds throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An action of the wrong length, with NaN/inf, or outside a Discrete space.
class InvalidActionError : public Error {
 public:
  using Error::Error;
};

// The episode protocol was broken: step before reset, step after the end.
class EpisodeStateError : public Error {
 public:
  using Error::Error;
};

// A task state that is malformed or belongs to another environment.
class TaskStateError : public Error {
 public:
  using Error::Error;
};

// Unknown environment id, unknown or ill-typed option, bad option value.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_ERROR_H_
