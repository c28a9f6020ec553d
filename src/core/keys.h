// Keyframes: where a time falls among keys with increasing times. Written once for every keyed
// quantity (camera, objects' motion, a school's goal path, a zone radius over time).
#pragma once

#include <cstddef>

namespace reel {

// Key i and the fraction s of the way to key i + 1: s in (0, 1] between the first and the last
// key; held outside them (at or before the first: i = 0, s = 0; at or after the last: i = n − 1,
// s = 0). `time(key)` gives a key's time.
struct KeySpan {
  std::size_t i = 0;
  double s = 0.0;
};

template <class Keys, class TimeOf>
KeySpan keySpan(const Keys& keys, double t, TimeOf time) {
  const std::size_t n = keys.size();
  if (n <= 1 || t <= time(keys[0])) return {};
  if (t >= time(keys[n - 1])) return {n - 1, 0.0};
  std::size_t i = 0;
  while (time(keys[i + 1]) < t) ++i;
  return {i, (t - time(keys[i])) / (time(keys[i + 1]) - time(keys[i]))};
}

// A value linear between keys (value(key) gives it), held outside them. Keys must not be empty.
template <class Keys, class TimeOf, class ValueOf>
auto keyedLinear(const Keys& keys, double t, TimeOf time, ValueOf value) -> decltype(value(keys[0])) {
  const KeySpan k = keySpan(keys, t, time);
  if (k.s == 0.0) return value(keys[k.i]);
  return (1.0 - k.s) * value(keys[k.i]) + k.s * value(keys[k.i + 1]);
}

}  // namespace reel
