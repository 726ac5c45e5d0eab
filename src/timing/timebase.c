/* The frame loop's clock (hz/display.h): a virtual counter, or the port's real clock through its hooks. */
#include "hz/display.h"

void hz_tb_init_virtual(hz_timebase_t *tb, int64_t start_ns)
{
    tb->virtual_time = 1;
    tb->vnow = start_ns;
    tb->clock_now = 0;
    tb->clock_sleep_until = 0;
}

int64_t hz_tb_now(const hz_timebase_t *tb)
{
    return tb->virtual_time ? tb->vnow : tb->clock_now();
}

void hz_tb_sleep_until(hz_timebase_t *tb, int64_t t)
{
    if (tb->virtual_time) {
        if (t > tb->vnow)
            tb->vnow = t;
        return;
    }
    tb->clock_sleep_until(t);
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
