/* The real clock of the frame loop's timebase (hz/display.h): CLOCK_MONOTONIC. */
#include "vsource.h"

#include <errno.h>
#include <time.h>

#include "clock.h"

static int64_t real_now(void)
{
    return hz_clock_ns();
}

static void real_sleep_until(int64_t t)
{
    if (t <= 0)
        return;
    struct timespec ts = { (time_t)(t / 1000000000), (long)(t % 1000000000) };
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
        ;
}

void hz_tb_init_real(hz_timebase_t *tb)
{
    tb->virtual_time = 0;
    tb->vnow = 0;
    tb->clock_now = real_now;
    tb->clock_sleep_until = real_sleep_until;
}
