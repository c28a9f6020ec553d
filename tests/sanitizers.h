// What a test needs to know about the sanitizer it runs under.
#pragma once

namespace reel::test {

// AddressSanitizer and ThreadSanitizer reserve more address space than a `ulimit -v` test allows:
// under them such a test runs without the limit, or not at all.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizerAddressSpace = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizerAddressSpace = true;
#else
inline constexpr bool kSanitizerAddressSpace = false;
#endif
#else
inline constexpr bool kSanitizerAddressSpace = false;
#endif

}  // namespace reel::test
