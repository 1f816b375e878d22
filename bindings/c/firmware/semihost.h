/* semihost: ARM semihosting (BKPT 0xAB), the debugger's console and exit, written here so the
 * firmware needs no C library. QEMU serves it with -semihosting-config enable=on. */
#ifndef SEMIHOST_H
#define SEMIHOST_H

#include <stddef.h>

/* Writes n bytes to the host's stdout; returns 0 on failure. */
int semihost_write(const char *bytes, size_t n);
/* The command line (-semihosting-config ...,arg=...) into buf, NUL-terminated; 0 on failure. */
int semihost_cmdline(char *buf, size_t cap);
/* Ends the program: QEMU exits with status 0 when ok, 1 otherwise. */
void semihost_exit(int ok) __attribute__((noreturn));

#endif /* SEMIHOST_H */
