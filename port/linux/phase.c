/* Progress lines on stderr (see phase.h). */
#include "phase.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clock.h"

bool hz_phase_muted = false;

void hz_phase_begin(hz_phase_t *p, bool quiet, const char *fmt, ...)
{
    memset(p, 0, sizeof *p);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->what, sizeof p->what, fmt, ap);
    va_end(ap);
    const char *env = getenv("HZ_PROGRESS");
    p->tty = hz_cli_stderr_is_tty();
    p->enabled = !quiet && !hz_phase_muted && (p->tty || (env && (!strcmp(env, "1") || !strcmp(env, "all"))));
    p->after_s = env && !strcmp(env, "all") ? 0.0 : HZ_PHASE_AFTER_S;
    p->t0 = p->last = hz_clock_ns();
}

void hz_phase_update(hz_phase_t *p, float fraction)
{
    if (!p->enabled || !(fraction < 1.0f)) /* the end says when it is done */
        return;
    int64_t now = hz_clock_ns();
    double s = (now - p->t0) * 1e-9;
    if (s < p->after_s || now - p->last < (p->tty ? 100000000 : 1000000000))
        return;
    p->last = now;
    p->shown = true;
    int pct = (int)(fraction * 100.0f);
    pct = pct < 0 ? 0 : pct > 100 ? 100 : pct;
    fprintf(stderr, "%s%s: %s: %d%% (%.1f s)%s", p->tty ? "\r" : "", hz_cli_prog, p->what, pct, s,
            p->tty ? " " : "\n");
    fflush(stderr);
}

void hz_phase_end(hz_phase_t *p)
{
    if (!p->enabled)
        return;
    double s = (hz_clock_ns() - p->t0) * 1e-9;
    if (!p->shown && s < p->after_s)
        return;
    fprintf(stderr, "%s%s: %s: done in %.1f s\n", p->tty ? "\r" : "", hz_cli_prog, p->what, s);
    fflush(stderr);
    p->shown = false;
}

void hz_phase_accel(void *user, float done)
{
    hz_phase_update((hz_phase_t *)user, done);
}
