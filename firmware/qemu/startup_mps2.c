/* Minimal Cortex-M4 startup for QEMU's mps2-an386: a vector table, the FPU enabled, then
 * newlib's rdimon crt0 (_start), which sets up the C runtime, runs main and exits through
 * semihosting with main's return value. Faults exit with code 100. */
#include <stdint.h>
#include <stdlib.h>

extern void _start(void);
extern uint32_t __stack;
void cbx_qemu_reset(void);
void cbx_qemu_fault(void);

#define CPACR (*(volatile uint32_t*)0xE000ED88u)

void cbx_qemu_reset(void) {
  CPACR |= 0xFu << 20; /* CP10, CP11: full access (FPU) */
  __asm volatile("dsb\n isb");
  _start();
  for (;;) {
  }
}

void cbx_qemu_fault(void) { _Exit(100); }

typedef struct {
  void* initial_sp;
  void (*handlers[15])(void);
} cbx_vector_table;

__attribute__((section(".vectors"), used)) static const cbx_vector_table vectors = {
    &__stack,
    {cbx_qemu_reset, cbx_qemu_fault, cbx_qemu_fault, cbx_qemu_fault, cbx_qemu_fault, cbx_qemu_fault,
     0, 0, 0, 0, cbx_qemu_fault, cbx_qemu_fault, 0, cbx_qemu_fault, cbx_qemu_fault}};
