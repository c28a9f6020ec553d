// A body's complete state as bytes, for World::snapshot and World::restore (resuming a run
// bit-exactly from any frame, and caches of simulated frames): plain values and arrays written
// in order and read back in the same order.
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "core/types.h"

namespace reel {

// Types copied byte for byte: trivially copyable ones (numbers, plain structs of them) and the
// fixed-size Eigen vectors and matrices (Vec3, Mat3), whose copies are bytewise too. Nothing that
// holds a pointer.
template <class T>
concept Bitwise = (std::is_trivially_copyable_v<T> && !std::is_pointer_v<T>) || std::is_same_v<T, Vec3> ||
                  std::is_same_v<T, Mat3>;

struct StateBlob {
  std::vector<std::byte> bytes;
};

class StateWriter {
 public:
  explicit StateWriter(StateBlob& out) : out_(out.bytes) {}
  template <Bitwise T>
  void put(const T& value) { append(&value, sizeof(T)); }
  template <Bitwise T>
  void put(const std::vector<T>& values) {
    put(static_cast<std::size_t>(values.size()));
    append(values.data(), values.size() * sizeof(T));
  }
  // So that one list of fields serves to write and to read: fields(writer) and fields(reader).
  template <class T>
  StateWriter& operator()(const T& v) {
    put(v);
    return *this;
  }

 private:
  void append(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::byte*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  std::vector<std::byte>& out_;
};

// Reads what a StateWriter wrote; a blob too short for what is asked leaves `ok()` false and the
// rest of the values untouched.
class StateReader {
 public:
  explicit StateReader(const StateBlob& in) : in_(in.bytes) {}
  template <Bitwise T>
  void get(T& value) { take(&value, sizeof(T)); }
  template <Bitwise T>
  void get(std::vector<T>& values) {
    std::size_t n = 0;
    get(n);
    if (!ok_ || n > (in_.size() - at_) / (sizeof(T) ? sizeof(T) : 1)) {
      ok_ = false;
      return;
    }
    values.resize(n);
    take(values.data(), n * sizeof(T));
  }
  template <class T>
  StateReader& operator()(T& v) {
    get(v);
    return *this;
  }
  bool ok() const { return ok_; }
  // Everything was read, nothing is left over.
  bool done() const { return ok_ && at_ == in_.size(); }

 private:
  void take(void* p, std::size_t n) {
    if (!ok_ || n > in_.size() - at_) {
      ok_ = false;
      return;
    }
    if (n) std::memcpy(p, in_.data() + at_, n);
    at_ += n;
  }
  const std::vector<std::byte>& in_;
  std::size_t at_ = 0;
  bool ok_ = true;
};

}  // namespace reel
