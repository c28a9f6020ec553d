// Two kinds of failure (pbrt's CHECK vs Error, Jolt's Result):
//  - programmer mistakes: REEL_CHECK (always on) and REEL_DCHECK (debug only) throw InternalError;
//  - bad input or a bad environment: functions return Result<T>, carrying an Error with a kind
//    that the app maps to an exit code (DESIGN 3) and one or more messages.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace reel {

enum class ErrorKind {
  BadInput = 2,   // usage, scene, asset
  Unstable = 3,   // the simulation went non-finite or ran away
  Output = 4,     // output could not be written
  Internal = 1,   // anything else
};

struct Error {
  ErrorKind kind = ErrorKind::Internal;
  std::vector<std::string> messages;  // one line each; the first is the headline

  Error() = default;
  Error(ErrorKind k, std::string message) : kind(k), messages{std::move(message)} {}
  Error(ErrorKind k, std::vector<std::string> lines) : kind(k), messages(std::move(lines)) {}
  const std::string& headline() const { return messages.front(); }
};

// A value or an Error. Deliberately small: ok(), value(), error().
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}          // NOLINT: implicit by design
  Result(Error error) : v_(std::move(error)) {}      // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// Result<void> equivalent.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : err_(std::move(error)), ok_(false) {}  // NOLINT
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { return err_; }

 private:
  Error err_;
  bool ok_ = true;
};

struct InternalError : std::logic_error {
  using std::logic_error::logic_error;
};

[[noreturn]] void failCheck(const char* file, int line, const char* cond, const std::string& msg);

}  // namespace reel

#define REEL_CHECK(cond, msg)                                               \
  do {                                                                      \
    if (!(cond)) ::reel::failCheck(__FILE__, __LINE__, #cond, (msg));       \
  } while (0)

#ifdef NDEBUG
#define REEL_DCHECK(cond, msg) \
  do {                         \
  } while (0)
#else
#define REEL_DCHECK(cond, msg) REEL_CHECK(cond, msg)
#endif
