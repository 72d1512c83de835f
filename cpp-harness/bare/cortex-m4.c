/* Reset for a C program on the emulated Cortex-M4 (mps2-an386.ld): the vector table, the
 * FPU switched on (the hard-float ABI passes doubles in its registers), .bss cleared, and
 * the C library's output sent to the host by semihosting (newlib's rdimon). A fault ends
 * the run with status 70, so a failing program cannot hang the emulator. After main, a
 * last line "#stack N" gives the deepest stack main used, everything it called included
 * (the words below the reset's frame are filled with a pattern first; the deepest one
 * overwritten marks it). */
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

extern uint32_t __bss_start__[], __bss_end__[], __stack_top[];
extern int main(void);
extern void initialise_monitor_handles(void);

static void fault(void) { _exit(70); }

/* the probed stack: this much below the reset's frame */
#define PROBED_BYTES (128u * 1024u)
#define PATTERN 0xC5A5C5A5u

static uint32_t *sp_now(void) {
    uint32_t *sp;
    __asm volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

void reset_handler(void);
void reset_handler(void) {
    /* CPACR: full access to coprocessors 10 and 11, the FPU */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm volatile("dsb\n\tisb" ::: "memory");
    for (uint32_t *p = __bss_start__; p < __bss_end__; ++p) *p = 0;
    initialise_monitor_handles();
    /* a margin below this frame for the fill loop's own calls (none) and the call to main */
    uint32_t *top = sp_now() - 16;
    uint32_t *bottom = top - PROBED_BYTES / sizeof(uint32_t);
    for (uint32_t *p = bottom; p < top; ++p) *(volatile uint32_t *)p = PATTERN;
    int status = main();
    uint32_t *deepest = bottom;
    while (deepest < top && *(volatile uint32_t *)deepest == PATTERN) ++deepest;
    printf("#stack %lu\n", (unsigned long)((uintptr_t)top - (uintptr_t)deepest));
    /* _exit, not exit: nothing is registered with atexit, and exit needs crti's _fini */
    fflush(stdout);
    _exit(status);
}

/* initial stack pointer, reset, then NMI, hard, memory-management, bus and usage faults */
__attribute__((section(".vectors"), used)) static void (*const vectors[7])(void) = {
    (void (*)(void))__stack_top, reset_handler, fault, fault, fault, fault, fault,
};
