/* semihost.c: see semihost.h. */
#include "semihost.h"

#include <stdint.h>

enum {
  SYS_OPEN = 0x01,
  SYS_WRITE = 0x05,
  SYS_GET_CMDLINE = 0x15,
  SYS_EXIT = 0x18,
  ADP_STOPPED_APPLICATION_EXIT = 0x20026,
  ADP_STOPPED_RUN_TIME_ERROR = 0x20023
};

static int32_t call(int32_t op, const void *arg) {
  register int32_t r0 __asm__("r0") = op;
  register const void *r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

int semihost_write(const char *bytes, size_t n) {
  static int32_t handle = -1;
  uint32_t block[3];
  if (handle < 0) {
    /* ":tt" opened for writing ("w" is mode 4) is the host's stdout. */
    static const char tt[] = ":tt";
    block[0] = (uint32_t)(uintptr_t)tt;
    block[1] = 4;
    block[2] = 3;
    handle = call(SYS_OPEN, block);
    if (handle < 0) {
      return 0;
    }
  }
  block[0] = (uint32_t)handle;
  block[1] = (uint32_t)(uintptr_t)bytes;
  block[2] = (uint32_t)n;
  return call(SYS_WRITE, block) == 0; /* the bytes NOT written */
}

int semihost_cmdline(char *buf, size_t cap) {
  uint32_t block[2];
  if (cap < 2) {
    return 0;
  }
  block[0] = (uint32_t)(uintptr_t)buf;
  block[1] = (uint32_t)(cap - 1);
  if (call(SYS_GET_CMDLINE, block) != 0 || block[1] >= cap) {
    return 0;
  }
  buf[block[1]] = '\0';
  return 1;
}

void semihost_exit(int ok) {
  /* On 32-bit ARM the reason is passed directly in r1. */
  call(SYS_EXIT, (const void *)(uintptr_t)(ok ? ADP_STOPPED_APPLICATION_EXIT
                                                : ADP_STOPPED_RUN_TIME_ERROR));
  for (;;) {
  }
}
