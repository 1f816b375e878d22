/* startup.c: the least a Cortex-M4F needs before main: a vector table, .data copied from
 * flash, .bss zeroed, the FPU switched on (the library is built for the hard-float ABI), the
 * stack painted so main can report its high-water mark. A fault (a `udf` trap from a Rust
 * panic, which the core never raises, or a bad access) is reported and fails the run. */
#include <stdint.h>

#include "semihost.h"

extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

/* The stack-paint word; firmware_stack_used() scans for the lowest overwritten one. */
#define PAINT 0xCCCCCCCCu

typedef void (*handler)(void);
struct vector_table {
  uint32_t *stack_top;
  handler handlers[15];
};

__attribute__((section(".vectors"), used)) const struct vector_table vectors = {
    _estack,
    {Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
     0, 0, 0, 0, Fault_Handler, Fault_Handler, 0, Fault_Handler, Fault_Handler}};

void Reset_Handler(void) {
  volatile uint32_t *cpacr = (volatile uint32_t *)0xE000ED88u;
  uint32_t *sp;
  /* CP10 and CP11: full access. */
  *cpacr |= 0xFu << 20;
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  for (uint32_t *s = _sidata, *d = _sdata; d < _edata;) {
    *d++ = *s++;
  }
  for (uint32_t *d = _sbss; d < _ebss;) {
    *d++ = 0;
  }
  /* Paint from the end of .bss up to a little below this frame. */
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  for (volatile uint32_t *p = _ebss; p < sp - 16;) {
    *p++ = PAINT;
  }
  semihost_exit(main() == 0);
}

/* Bytes of stack used so far (the high-water mark) and the stack's size. */
uint32_t firmware_stack_used(void) {
  const uint32_t *p = _ebss;
  while (p < _estack && *p == PAINT) {
    p++;
  }
  return (uint32_t)((uintptr_t)_estack - (uintptr_t)p);
}

void Fault_Handler(void) {
  static const char msg[] = "error: fault (a trap or a bad access)\n";
  semihost_write(msg, sizeof msg - 1);
  semihost_exit(0);
}
