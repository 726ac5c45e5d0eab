/*
 * clock.h — monotonic time for the Linux port.
 *
 * Contract: hz_clock_ns() is CLOCK_MONOTONIC in nanoseconds (the clock the kernel stamps GPIO edge events and
 * V4L2 buffers with, so they compare directly). It never goes backwards.
 */
#ifndef HZ_PORT_CLOCK_H
#define HZ_PORT_CLOCK_H

#include <stdint.h>

int64_t hz_clock_ns(void);

#endif
