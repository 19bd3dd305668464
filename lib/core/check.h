#pragma once
/// @file
/// Programmer-error checks (DRAKE_DEMAND / DRAKE_ASSERT style). Input errors are never checked
/// with these: untrusted input is validated and rejected with a reason (see detection.h).

#include <cstdio>
#include <cstdlib>

namespace mvtrack::core::internal {
[[noreturn]] inline void CheckFailed(const char* cond,
                                     const char* file,
                                     int line,
                                     const char* msg) {
  std::fprintf(stderr,
               "mvtrack: check failed: %s at %s:%d%s%s\n",
               cond,
               file,
               line,
               msg[0] != '\0' ? ": " : "",
               msg);
  std::abort();
}
}  // namespace mvtrack::core::internal

/// Always-on check; aborts with file, line and message.
#define MVTRACK_CHECK_MSG(cond, msg)                                                     \
  do {                                                                                   \
    if (!(cond)) ::mvtrack::core::internal::CheckFailed(#cond, __FILE__, __LINE__, msg); \
  } while (0)
#define MVTRACK_CHECK(cond) MVTRACK_CHECK_MSG(cond, "")

/// Debug-only check.
#ifdef NDEBUG
#define MVTRACK_DCHECK(cond) \
  do {                       \
  } while (false && (cond))
#else
#define MVTRACK_DCHECK(cond) MVTRACK_CHECK(cond)
#endif
