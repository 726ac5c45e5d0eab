/* Real and virtual clocks for the frame loop (see vsource.h). */
#include "vsource.h"

#include <errno.h>
#include <time.h>

#include "clock.h"

void hz_tb_init_real(hz_timebase_t *tb)
{
    tb->virtual_time = 0;
    tb->vnow = 0;
}

void hz_tb_init_virtual(hz_timebase_t *tb, int64_t start_ns)
{
    tb->virtual_time = 1;
    tb->vnow = start_ns;
}

int64_t hz_tb_now(const hz_timebase_t *tb)
{
    return tb->virtual_time ? tb->vnow : hz_clock_ns();
}

void hz_tb_sleep_until(hz_timebase_t *tb, int64_t t)
{
    if (tb->virtual_time) {
        if (t > tb->vnow)
            tb->vnow = t;
        return;
    }
    if (t <= 0)
        return;
    struct timespec ts = { (time_t)(t / 1000000000), (long)(t % 1000000000) };
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
        ;
}

void hz_tb_advance(hz_timebase_t *tb, int64_t dt)
{
    if (tb->virtual_time && dt > 0)
        tb->vnow += dt;
}

void hz_vsource_close(hz_vsource_t *s)
{
    if (s && s->close) {
        s->close(s);
        s->close = 0;
    }
}

void hz_sink_close(hz_sink_t *s)
{
    if (s && s->close) {
        s->close(s);
        s->close = 0;
    }
}
