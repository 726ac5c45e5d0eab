/*
 * The coverage counters of a fuzz target (libFuzzer's inline 8-bit counters, the __sancov_cntrs section), for a
 * target that runs code in a child process and copies the child's counters back (fuzz_import.c). Compiled
 * without coverage instrumentation: in an instrumented file, naming the section's bounds collides with the
 * instrumentation's own references to them, and libFuzzer then registers no counters at all.
 */
#include <stddef.h>
#include <stdint.h>

extern uint8_t __start___sancov_cntrs[] __attribute__((weak, visibility("hidden")));
extern uint8_t __stop___sancov_cntrs[] __attribute__((weak, visibility("hidden")));

uint8_t *hz_fuzz_counters(size_t *n);
uint8_t *hz_fuzz_counters(size_t *n)
{
    *n = __start___sancov_cntrs ? (size_t)(__stop___sancov_cntrs - __start___sancov_cntrs) : 0;
    return __start___sancov_cntrs;
}
