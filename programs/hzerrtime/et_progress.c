/* One-line progress bar (see et_progress.h). */
#include "et_progress.h"

#include <string.h>

#include "clock.h"

#define BAR 30

static void draw(hz_progress_t *p, int pct)
{
    char bar[BAR + 1];
    int fill = (int)((uint64_t)BAR * p->done / (p->total ? p->total : 1));
    for (int i = 0; i < BAR; i++)
        bar[i] = i < fill ? '#' : '-';
    bar[BAR] = '\0';
    double elapsed = (double)(hz_clock_ns() - p->t0_ns) * 1e-9;
    fprintf(p->f, "\r%-28.28s [%s] %3d%%  %llu/%llu", p->label, bar, pct, (unsigned long long)p->done,
            (unsigned long long)p->total);
    if (p->done > 0 && p->done < p->total)
        fprintf(p->f, "  eta %.0f s ", elapsed / (double)p->done * (double)(p->total - p->done));
    else
        fprintf(p->f, "            ");
    fflush(p->f);
    p->shown = pct;
}

void hz_progress_begin(hz_progress_t *p, FILE *f, bool enabled, uint64_t total)
{
    memset(p, 0, sizeof *p);
    p->f = f;
    p->enabled = enabled && f;
    p->total = total;
    p->t0_ns = hz_clock_ns();
    p->shown = -1;
}

void hz_progress_label(hz_progress_t *p, const char *label)
{
    snprintf(p->label, sizeof p->label, "%s", label);
    if (p->enabled)
        draw(p, p->total ? (int)(100 * p->done / p->total) : 100);
}

void hz_progress_step(hz_progress_t *p, uint64_t n)
{
    p->done += n;
    if (p->done > p->total)
        p->done = p->total;
    int pct = p->total ? (int)(100 * p->done / p->total) : 100;
    if (p->enabled && pct != p->shown)
        draw(p, pct);
}

void hz_progress_end(hz_progress_t *p)
{
    if (!p->enabled)
        return;
    p->done = p->total;
    draw(p, 100);
    fputc('\n', p->f);
    fflush(p->f);
}
