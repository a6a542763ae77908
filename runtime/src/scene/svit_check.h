#pragma once
// SVIT_CHECK: an internal invariant, checked in every build. A failure is a
// bug in svit, never bad input (bad input gets a Status): it prints the
// expression, its operands where given, and the place, then aborts.
//
//   SVIT_CHECK(index < size, "index %zu, size %zu", index, size);

#include <cstdio>
#include <cstdlib>

#define SVIT_CHECK(condition, ...)                                                        \
  do {                                                                                    \
    if (!(condition)) {                                                                   \
      std::fprintf(stderr, "%s:%d: svit internal check failed: %s: ", __FILE__, __LINE__, \
                   #condition);                                                           \
      std::fprintf(stderr, __VA_ARGS__);                                                  \
      std::fputc('\n', stderr);                                                           \
      std::abort();                                                                       \
    }                                                                                     \
  } while (false)
