/* Reset for a C program on the emulated Cortex-M4 (mps2-an386.ld): the vector table, the
 * FPU switched on (the hard-float ABI passes doubles in its registers), .bss cleared, and
 * the C library's output sent to the host by semihosting (newlib's rdimon). A fault ends
 * the run with status 70, so a failing program cannot hang the emulator. */
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

extern uint32_t __bss_start__[], __bss_end__[], __stack_top[];
extern int main(void);
extern void initialise_monitor_handles(void);

static void fault(void) { _exit(70); }

void reset_handler(void);
void reset_handler(void) {
    /* CPACR: full access to coprocessors 10 and 11, the FPU */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm volatile("dsb\n\tisb" ::: "memory");
    for (uint32_t *p = __bss_start__; p < __bss_end__; ++p) *p = 0;
    initialise_monitor_handles();
    int status = main();
    /* _exit, not exit: nothing is registered with atexit, and exit needs crti's _fini */
    fflush(stdout);
    _exit(status);
}

/* initial stack pointer, reset, then NMI, hard, memory-management, bus and usage faults */
__attribute__((section(".vectors"), used)) static void (*const vectors[7])(void) = {
    (void (*)(void))__stack_top, reset_handler, fault, fault, fault, fault, fault,
};
