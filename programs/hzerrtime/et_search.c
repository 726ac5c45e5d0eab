/* The adaptive operating point (see et_search.h). */
#include "et_search.h"

#include <math.h>
#include <string.h>

#include "et_render.h"
#include "fileio.h"

typedef char probes_match_steps[HZ_ET_SEARCH_PROBES == 2 + HZ_ET_SEARCH_STEPS ? 1 : -1];

/* One probe: `family` at threshold tau through a whole errtime run, its row appended. */
static hz_status_t probe(const hz_et_sequence_t *seq, const hz_et_method_t *reference, const hz_et_method_t *family,
                        const char *name, double tau, const hz_et_config_t *cfg, hz_et_row_t *rows, size_t max,
                        size_t *n, hz_error_t *err)
{
    if (*n >= max)
        return hz_error_set(err, HZ_E_RANGE, "adaptive search: more than %zu probes", max);
    hz_et_render_params_t p = *(const hz_et_render_params_t *)family->params;
    p.adaptive_tau = (float)tau;
    hz_et_method_t m = *family;
    m.name = name;
    m.value = (double)(float)tau; /* the threshold as the renderer sees it */
    m.params = &p;
    hz_status_t s = hz_et_run(seq, reference, &m, 1, cfg, &rows[*n], err);
    if (s == HZ_OK)
        (*n)++;
    return s;
}

static bool reaches(const hz_et_row_t *r, double psnr9)
{
    return r->psnr_srgb8 >= psnr9; /* NaN never reaches */
}

hz_status_t hz_et_adaptive_search(const hz_et_sequence_t *seq, const hz_et_method_t *reference,
                                  const hz_et_method_t *family, const hz_et_row_t *row9, const hz_et_row_t *row16,
                                  const hz_et_config_t *cfg, hz_et_row_t *probes, size_t max_probes, size_t *nprobes,
                                  hz_et_search_t *res, hz_error_t *err)
{
    const hz_et_render_params_t *fp = family->params;
    if (!fp || fp->mode != HZ_MODE_ADAPTIVE)
        return hz_error_set(err, HZ_E_INVALID_ARG, "adaptive search: %s is not an adaptive method", family->name);
    char name[48];
    snprintf(name, sizeof name, "%s-search", family->name);
    const double psnr9 = row9->psnr_srgb8;
    const size_t first = *nprobes;
    hz_status_t s;
    /* lo: the largest tau known to reach; hi: the smallest known not to */
    double lo = -1.0, hi = -1.0;
    if ((s = probe(seq, reference, family, name, 1.0, cfg, probes, max_probes, nprobes, err)) != HZ_OK)
        return s;
    if (reaches(&probes[*nprobes - 1], psnr9)) {
        lo = 1.0;
    } else {
        hi = 1.0;
        if ((s = probe(seq, reference, family, name, HZ_ET_SEARCH_TAU_MIN, cfg, probes, max_probes, nprobes,
                       err)) != HZ_OK)
            return s;
        if (reaches(&probes[*nprobes - 1], psnr9)) {
            lo = HZ_ET_SEARCH_TAU_MIN;
            for (int i = 0; i < HZ_ET_SEARCH_STEPS; i++) {
                const double mid = sqrt(lo * hi);
                if ((s = probe(seq, reference, family, name, mid, cfg, probes, max_probes, nprobes, err)) != HZ_OK)
                    return s;
                if (reaches(&probes[*nprobes - 1], psnr9))
                    lo = mid;
                else
                    hi = mid;
            }
        }
    }
    /* the answer's row: the largest probed tau that reached, else the smallest probed */
    const hz_et_row_t *best = NULL;
    for (size_t i = first; i < *nprobes; i++) {
        const hz_et_row_t *r = &probes[i];
        if (lo > 0.0 ? (reaches(r, psnr9) && (!best || r->value > best->value)) : (!best || r->value < best->value))
            best = r;
    }
    memset(res, 0, sizeof *res);
    snprintf(res->scene, sizeof res->scene, "%s", row9->scene);
    snprintf(res->method, sizeof res->method, "%s", family->name);
    res->width = row9->width, res->height = row9->height;
    res->probes = (uint32_t)(*nprobes - first);
    res->reached = lo > 0.0;
    res->tau = best->value;
    res->psnr = best->psnr_srgb8, res->flip = best->flip, res->ms = best->ms_median;
    res->camera_rays = best->camera_rays_per_pixel;
    res->psnr9 = row9->psnr_srgb8, res->flip9 = row9->flip, res->ms9 = row9->ms_median;
    res->psnr16 = row16->psnr_srgb8, res->flip16 = row16->flip, res->ms16 = row16->ms_median;
    res->time_vs_9 = res->ms9 > 0.0 ? res->ms / res->ms9 : NAN;
    res->rays_vs_9 = res->camera_rays / 9.0;
    return HZ_OK;
}

/* ---- files ---- */

static void csv_line(FILE *f, const hz_et_search_t *r)
{
    hz_et_csv_text(f, r->scene);
    fputc(',', f);
    hz_et_csv_text(f, r->method);
    fprintf(f, ",%u,%u,%u,%d,%.4f,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
            (unsigned)r->width, (unsigned)r->height, (unsigned)r->probes, r->reached, r->tau, r->psnr, r->psnr9,
            r->psnr16, r->flip, r->flip9, r->flip16, r->ms, r->ms9, r->ms16, r->time_vs_9, r->camera_rays,
            r->rays_vs_9);
}

hz_status_t hz_et_write_search_csv(const char *path, const hz_et_search_t *r, size_t n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    fprintf(out.f, "%s\n", HZ_ET_SEARCH_CSV_HEADER);
    for (size_t i = 0; i < n; i++)
        csv_line(out.f, &r[i]);
    return hz_out_commit(&out, err);
}

void hz_et_print_search(FILE *f, const hz_et_search_t *r, size_t n)
{
    fprintf(f, "### adaptive operating point: the largest tau whose PSNR reaches full-frame 9 spp's\n\n");
    fprintf(f, "| scene | size | method | probes | tau | PSNR dB | 9 spp | 16 spp | FLIP | 9 spp | 16 spp | ms | "
               "9 spp ms | time vs 9 spp | camera rays/px | vs 9 spp |\n");
    fprintf(f, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (size_t i = 0; i < n; i++) {
        const hz_et_search_t *x = &r[i];
        char tau[32];
        snprintf(tau, sizeof tau, x->reached ? "%.3g" : "none (%.3g)", x->tau);
        fprintf(f, "| %s | %ux%u | %s | %u | %s | %.2f | %.2f | %.2f | %.4f | %.4f | %.4f | %.1f | %.1f | %.2fx | "
                   "%.2f | %.1f%% |\n",
                x->scene, (unsigned)x->width, (unsigned)x->height, x->method, (unsigned)x->probes, tau, x->psnr,
                x->psnr9, x->psnr16, x->flip, x->flip9, x->flip16, x->ms, x->ms9, x->time_vs_9, x->camera_rays,
                100.0 * x->rays_vs_9);
    }
}

hz_status_t hz_et_write_search_markdown(const char *path, const hz_et_search_t *r, size_t n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    hz_et_print_search(out.f, r, n);
    return hz_out_commit(&out, err);
}
