/*
 * The C tests' checks: CHECK(cond) and CHECK_RESULT(call, want) count into `passed` and
 * `failed` (one pair per test program, which prints them at its end) and name the file, line
 * and, for a result, both codes on a failure.
 */
#ifndef SDS_CTEST_CHECK_H
#define SDS_CTEST_CHECK_H

#include <stdio.h>

#include "sds_monitor.h"

static unsigned passed;
static unsigned failed;

#define CHECK(cond)                                                      \
  do {                                                                   \
    if (cond) {                                                          \
      passed++;                                                          \
    } else {                                                             \
      failed++;                                                          \
      fprintf(stderr, "%s:%d: FAILED: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                    \
  } while (0)

/* CHECK that a call returned `want`, naming both codes on a failure. */
#define CHECK_RESULT(call, want)                                                          \
  do {                                                                                    \
    sds_result got_ = (call);                                                             \
    if (got_ == (want)) {                                                                 \
      passed++;                                                                           \
    } else {                                                                              \
      failed++;                                                                           \
      fprintf(stderr, "%s:%d: FAILED: %s returned %u (%s), expected %u (%s)\n", __FILE__, \
              __LINE__, #call, (unsigned)got_, sds_result_str(got_), (unsigned)(want),    \
              sds_result_str(want));                                                      \
    }                                                                                     \
  } while (0)

#endif
