/* errtime's CSV, Markdown and SVG writers and the Pareto front (see et_report.h). */
#include "et_report.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fileio.h"

/* ---- Pareto front ---- */

static bool dominated(double t, double e, double t2, double e2, bool lower_better)
{
    bool no_worse = t2 <= t && (lower_better ? e2 <= e : e2 >= e);
    bool better = t2 < t || (lower_better ? e2 < e : e2 > e);
    return no_worse && better;
}

void hz_et_pareto(hz_et_row_t *rows, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        hz_et_row_t *r = &rows[i];
        r->pareto_flip = !isnan(r->ms_median) && !isnan(r->flip);
        r->pareto_psnr = !isnan(r->ms_median) && !isnan(r->psnr_srgb8);
        for (size_t j = 0; j < n; j++) {
            const hz_et_row_t *o = &rows[j];
            if (j == i || strcmp(o->scene, r->scene) != 0 || isnan(o->ms_median))
                continue;
            if (!isnan(o->flip) && dominated(r->ms_median, r->flip, o->ms_median, o->flip, true))
                r->pareto_flip = false;
            if (!isnan(o->psnr_srgb8) && dominated(r->ms_median, r->psnr_srgb8, o->ms_median, o->psnr_srgb8, false))
                r->pareto_psnr = false;
        }
    }
}

/* ---- helpers ---- */

static const char *num(char *buf, size_t size, const char *fmt, double v)
{
    if (isnan(v))
        snprintf(buf, size, "nan");
    else if (isinf(v))
        snprintf(buf, size, v > 0 ? "inf" : "-inf");
    else
        snprintf(buf, size, fmt, v);
    return buf;
}

void hz_et_csv_text(FILE *f, const char *s)
{
    if (!strpbrk(s, ",\"\n\r")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

static void xml_text(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

/* Markdown table cells: a '|' would split the cell. */
static void md_text(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '|')
            fputs("\\|", f);
        else
            fputc(*s, f);
    }
}

static hz_status_t finish(hz_out_t *out, hz_error_t *err)
{
    return hz_out_commit(out, err);
}

/* ---- CSV ---- */

hz_status_t hz_et_write_csv(const char *path, const hz_et_row_t *rows, size_t n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    fprintf(f, "%s\n", HZ_ET_CSV_HEADER);
    for (size_t i = 0; i < n; i++) {
        const hz_et_row_t *r = &rows[i];
        char b[10][48];
        hz_et_csv_text(f, r->scene);
        fputc(',', f);
        hz_et_csv_text(f, r->method);
        fputc(',', f);
        hz_et_csv_text(f, r->knob);
        fprintf(f, ",%s,%u,%u,%u,%u,%u,%s,%s,%s,%s,%s,%s,%s,%u,%s,%s,%d,%d,", num(b[0], 48, "%g", r->value),
                (unsigned)r->width, (unsigned)r->height, (unsigned)r->frames, (unsigned)r->measured,
                (unsigned)r->refresh_hz, num(b[1], 48, "%.4f", r->ms_median), num(b[2], 48, "%.4f", r->ms_p99),
                num(b[3], 48, "%.0f", r->rays_per_frame), num(b[4], 48, "%.4f", r->psnr_srgb8),
                num(b[5], 48, "%.4f", r->psnr_linear), num(b[6], 48, "%.6f", r->ssim), num(b[7], 48, "%.6f", r->flip),
                (unsigned)r->di_k, num(b[8], 48, "%.6f", r->di_flip), num(b[9], 48, "%.4f", r->di_psnr_srgb8),
                r->pareto_flip, r->pareto_psnr);
        fprintf(f, "%s,%s\n", num(b[0], 48, "%.4f", r->camera_rays_per_pixel),
                num(b[1], 48, "%.4f", r->camera_rays_per_pixel / 9.0));
    }
    return finish(&out, err);
}

/* ---- Markdown ---- */

/* Seed 003's Fig. 7 for one scene: the colour-only and multiple-measures rows paired by their tau_col, with the
 * paper's "sample ratio" (camera rays against fixed 16 spp's). Nothing when the scene lacks either family. */
static void print_fig7(FILE *f, const hz_et_row_t *rows, size_t n, const char *scene)
{
    static const char *const fam[2] = { "adaptive-colour-only", "adaptive-multiple" };
    bool any[2] = { false, false };
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 2; k++)
            any[k] = any[k] || (!strcmp(rows[i].scene, scene) && !strcmp(rows[i].method, fam[k]));
    if (!any[0] || !any[1])
        return;
    fprintf(f, "\nSeed 003 Fig. 7, the colour measure alone against multiple measures (sample ratio: camera rays "
               "against fixed 16 spp's):\n\n");
    fprintf(f, "| tau-col | colour only: sample ratio | PSNR sRGB8 dB | mean FLIP | ms/frame | "
               "multiple: sample ratio | PSNR sRGB8 dB | mean FLIP | ms/frame |\n");
    fprintf(f, "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (size_t i = 0; i < n; i++) {
        if (strcmp(rows[i].scene, scene) != 0 || strcmp(rows[i].method, fam[0]) != 0)
            continue;
        const hz_et_row_t *pair[2] = { &rows[i], NULL };
        for (size_t j = 0; j < n && !pair[1]; j++)
            if (!strcmp(rows[j].scene, scene) && !strcmp(rows[j].method, fam[1]) && rows[j].value == rows[i].value)
                pair[1] = &rows[j];
        char b[48];
        fprintf(f, "| %s", num(b, sizeof b, "%g", rows[i].value));
        for (int k = 0; k < 2; k++) {
            const hz_et_row_t *r = pair[k];
            if (!r) {
                fputs(" | - | - | - | -", f);
                continue;
            }
            fprintf(f, " | %s%%", num(b, sizeof b, "%.2f", 100.0 * r->camera_rays_per_pixel / 16.0));
            fprintf(f, " | %s", num(b, sizeof b, "%.2f", r->psnr_srgb8));
            fprintf(f, " | %s", num(b, sizeof b, "%.4f", r->flip));
            fprintf(f, " | %s", num(b, sizeof b, "%.3f", r->ms_median));
        }
        fputs(" |\n", f);
    }
}

void hz_et_print_markdown(FILE *f, const hz_et_row_t *rows, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        bool first = true;
        for (size_t j = 0; j < i; j++)
            if (!strcmp(rows[j].scene, rows[i].scene))
                first = false;
        if (!first)
            continue;
        const hz_et_row_t *h = &rows[i];
        fprintf(f, "%s### ", i ? "\n" : "");
        md_text(f, h->scene);
        fprintf(f, " — %ux%u, %u frames at %u Hz (%u warm-up), display-integrated over k = %u\n\n",
                (unsigned)h->width, (unsigned)h->height, (unsigned)h->frames, (unsigned)h->refresh_hz,
                (unsigned)(h->frames - h->measured), (unsigned)h->di_k);
        fprintf(f, "| method | setting | ms/frame | ms p99 | Mrays/frame | mean FLIP | PSNR sRGB8 dB | "
                   "PSNR linear dB | SSIM | DI FLIP | DI PSNR dB | camera rays/px | vs 9 spp | Pareto |\n");
        fprintf(f, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
        for (size_t j = i; j < n; j++) {
            const hz_et_row_t *r = &rows[j];
            if (strcmp(r->scene, h->scene) != 0)
                continue;
            char b[10][48];
            fputs("| ", f);
            md_text(f, r->method);
            fputs(" | ", f);
            md_text(f, r->knob);
            char rpp[2][48];
            if (isnan(r->camera_rays_per_pixel))
                snprintf(rpp[0], 48, "-"), snprintf(rpp[1], 48, "-");
            else
                snprintf(rpp[0], 48, "%.2f", r->camera_rays_per_pixel),
                    snprintf(rpp[1], 48, "%.1f%%", 100.0 * r->camera_rays_per_pixel / 9.0);
            fprintf(f, "=%s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s%s%s |\n",
                    num(b[0], 48, "%g", r->value),
                    num(b[1], 48, "%.3f", r->ms_median), num(b[2], 48, "%.3f", r->ms_p99),
                    num(b[3], 48, "%.3f", r->rays_per_frame * 1e-6), num(b[4], 48, "%.4f", r->flip),
                    num(b[5], 48, "%.2f", r->psnr_srgb8), num(b[6], 48, "%.2f", r->psnr_linear),
                    num(b[7], 48, "%.4f", r->ssim), num(b[8], 48, "%.4f", r->di_flip),
                    num(b[9], 48, "%.2f", r->di_psnr_srgb8), rpp[0], rpp[1], r->pareto_flip ? "FLIP" : "",
                    r->pareto_flip && r->pareto_psnr ? ", " : "", r->pareto_psnr ? "PSNR" : "");
        }
        print_fig7(f, rows, n, h->scene);
    }
}

hz_status_t hz_et_write_markdown(const char *path, const hz_et_row_t *rows, size_t n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    hz_et_print_markdown(out.f, rows, n);
    return finish(&out, err);
}

/* ---- SVG ---- */

#define SVG_W 1000
#define PANEL_W 400
#define PANEL_H 300
#define PANEL_TOP 60
#define PANEL_LEFT0 70
#define PANEL_GAP 110

static const char *const palette[] = { "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                       "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22" };

typedef struct axis {
    double lo, hi;
    bool log;
} axis_t;

static double nice_step(double range)
{
    double raw = range / 5.0, mag = pow(10.0, floor(log10(raw))), r = raw / mag;
    return (r <= 1.0 ? 1.0 : r <= 2.0 ? 2.0 : r <= 5.0 ? 5.0 : 10.0) * mag;
}

static double map_axis(const axis_t *a, double v, double p0, double p1)
{
    double t = a->log ? (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo)) : (v - a->lo) / (a->hi - a->lo);
    return p0 + t * (p1 - p0);
}

typedef struct point {
    double x, y;
    const hz_et_row_t *row;
} point_t;

static double plot_ms(const hz_et_row_t *r)
{
    return r->ms_median > 1e-6 ? r->ms_median : 1e-6;
}

static void draw_panel(FILE *f, const hz_et_row_t *const *rows, size_t n, int panel, const axis_t *ax,
                       const char *const *methods, size_t nm)
{
    const bool is_flip = panel == 0;
    double left = PANEL_LEFT0 + panel * (PANEL_W + PANEL_GAP), right = left + PANEL_W;
    double top = PANEL_TOP, bottom = top + PANEL_H;
    /* y axis range */
    double ylo = INFINITY, yhi = -INFINITY;
    bool any_inf = false;
    for (size_t i = 0; i < n; i++) {
        double v = is_flip ? rows[i]->flip : rows[i]->psnr_srgb8;
        if (isinf(v))
            any_inf = true;
        if (!isfinite(v))
            continue;
        ylo = fmin(ylo, v);
        yhi = fmax(yhi, v);
    }
    axis_t ay = { 0, 1, false };
    if (is_flip) {
        ay.lo = 0.0;
        ay.hi = isfinite(yhi) && yhi > 0 ? yhi * 1.1 : 1.0;
    } else if (isfinite(ylo)) {
        ay.lo = floor(ylo) - 1.0;
        ay.hi = ceil(yhi) + 1.0;
    } else {
        ay.lo = 0.0;
        ay.hi = 60.0;
    }
    double step = nice_step(ay.hi - ay.lo);
    ay.hi = ceil(ay.hi / step - 1e-9) * step;
    if (!is_flip)
        ay.lo = floor(ay.lo / step + 1e-9) * step;

    fprintf(f, "<g class=\"panel\">\n");
    fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"#333\"/>\n", left, top,
            PANEL_W, PANEL_H);
    /* grid and ticks */
    for (double v = ay.lo; v <= ay.hi + step * 1e-6; v += step) {
        double y = map_axis(&ay, v, bottom, top);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", left, y, right, y);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">%g</text>\n", left - 6, y + 4,
                fabs(v) < step * 1e-6 ? 0.0 : v);
    }
    for (int d = (int)floor(log10(ax->lo) + 1e-9); d <= (int)ceil(log10(ax->hi) - 1e-9); d++) {
        static const double mult[3] = { 1, 2, 5 };
        for (int m = 0; m < 3; m++) {
            double v = mult[m] * pow(10.0, d);
            if (v < ax->lo * (1 - 1e-9) || v > ax->hi * (1 + 1e-9))
                continue;
            double x = map_axis(ax, v, left, right);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n", x, top, x, bottom,
                    m == 0 ? "#ccc" : "#eee");
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"middle\">%g</text>\n", x,
                    bottom + 16, v);
        }
    }
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"13\" text-anchor=\"middle\">ms per displayed frame "
               "(median, log scale)</text>\n", (left + right) / 2, bottom + 36);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"14\" font-weight=\"bold\" text-anchor=\"middle\">%s</text>\n",
            (left + right) / 2, top - 10,
            is_flip ? "mean FLIP (lower is better)" : "PSNR on sRGB 8-bit, dB (higher is better)");

    /* one polyline per method, in knob order */
    point_t pts[256];
    for (size_t mi = 0; mi < nm; mi++) {
        size_t np = 0;
        for (size_t i = 0; i < n && np < 256; i++) {
            if (strcmp(rows[i]->method, methods[mi]) != 0)
                continue;
            double v = is_flip ? rows[i]->flip : rows[i]->psnr_srgb8;
            if (isnan(v))
                continue;
            point_t p = { map_axis(ax, plot_ms(rows[i]), left, right),
                          isinf(v) ? (v > 0 ? top : bottom) : map_axis(&ay, v, bottom, top), rows[i] };
            size_t k = np++;
            while (k > 0 && pts[k - 1].row->value > p.row->value) { /* insertion sort by knob value */
                pts[k] = pts[k - 1];
                k--;
            }
            pts[k] = p;
        }
        const char *col = palette[mi % (sizeof palette / sizeof palette[0])];
        fprintf(f, "<polyline class=\"series\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", col);
        for (size_t k = 0; k < np; k++)
            fprintf(f, "%s%.1f,%.1f", k ? " " : "", pts[k].x, pts[k].y);
        fprintf(f, "\"/>\n");
        for (size_t k = 0; k < np; k++) {
            char b[48];
            fprintf(f, "<circle class=\"point\" cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", pts[k].x, pts[k].y,
                    col);
            fprintf(f, "<text class=\"knob\" x=\"%.1f\" y=\"%.1f\" font-size=\"11\" fill=\"%s\">%s</text>\n",
                    pts[k].x + 6, pts[k].y - 6, col, num(b, sizeof b, "%g", pts[k].row->value));
        }
    }
    /* Pareto front: rings, and a dashed staircase in time order */
    size_t np = 0;
    for (size_t i = 0; i < n && np < 256; i++) {
        double v = is_flip ? rows[i]->flip : rows[i]->psnr_srgb8;
        if (!(is_flip ? rows[i]->pareto_flip : rows[i]->pareto_psnr) || isnan(v))
            continue;
        point_t p = { map_axis(ax, plot_ms(rows[i]), left, right),
                      isinf(v) ? (v > 0 ? top : bottom) : map_axis(&ay, v, bottom, top), rows[i] };
        size_t k = np++;
        while (k > 0 && pts[k - 1].x > p.x) {
            pts[k] = pts[k - 1];
            k--;
        }
        pts[k] = p;
    }
    if (np > 0) {
        fprintf(f, "<polyline class=\"front\" fill=\"none\" stroke=\"#555\" stroke-dasharray=\"4 3\" points=\"");
        for (size_t k = 0; k < np; k++) {
            if (k)
                fprintf(f, " %.1f,%.1f", pts[k].x, pts[k - 1].y);
            fprintf(f, " %.1f,%.1f", pts[k].x, pts[k].y);
        }
        fprintf(f, "\"/>\n");
        for (size_t k = 0; k < np; k++)
            fprintf(f, "<circle class=\"pareto\" cx=\"%.1f\" cy=\"%.1f\" r=\"7\" fill=\"none\" stroke=\"#000\"/>\n",
                    pts[k].x, pts[k].y);
    }
    if (any_inf && !is_flip)
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" text-anchor=\"end\">inf</text>\n", left - 6, top - 2);
    fprintf(f, "</g>\n");
}

hz_status_t hz_et_write_svg(const char *path, const hz_et_row_t *rows_in, size_t n_in, const char *scene,
                            hz_error_t *err)
{
    const hz_et_row_t *rows[256];
    size_t n = 0;
    for (size_t i = 0; i < n_in; i++)
        if (!strcmp(rows_in[i].scene, scene)) {
            if (n == 256)
                return hz_error_set(err, HZ_E_RANGE, "%s: more than 256 rows for scene %s", path, scene);
            rows[n++] = &rows_in[i];
        }
    if (n == 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "%s: no rows for scene %s", path, scene);
    const char *methods[64];
    size_t nm = 0;
    for (size_t i = 0; i < n; i++) {
        size_t k = 0;
        while (k < nm && strcmp(methods[k], rows[i]->method) != 0)
            k++;
        if (k == nm) {
            if (nm == 64)
                return hz_error_set(err, HZ_E_RANGE, "%s: more than 64 methods", path);
            methods[nm++] = rows[i]->method;
        }
    }
    axis_t ax = { INFINITY, 0, true };
    for (size_t i = 0; i < n; i++) {
        double t = plot_ms(rows[i]);
        if (isfinite(t)) {
            ax.lo = fmin(ax.lo, t);
            ax.hi = fmax(ax.hi, t);
        }
    }
    if (!isfinite(ax.lo)) {
        ax.lo = 1;
        ax.hi = 10;
    }
    ax.lo = pow(10.0, floor(log10(ax.lo / 1.2)));
    ax.hi = pow(10.0, ceil(log10(ax.hi * 1.2)));

    int legend_rows = (int)((nm + 3) / 4);
    int height = PANEL_TOP + PANEL_H + 60 + 20 * legend_rows + 10;
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    FILE *f = out.f;
    const hz_et_row_t *h = rows[0];
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
               "font-family=\"sans-serif\">\n", SVG_W, height, SVG_W, height);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"#fff\"/>\n");
    fprintf(f, "<text x=\"%d\" y=\"22\" font-size=\"16\" font-weight=\"bold\" text-anchor=\"middle\">", SVG_W / 2);
    xml_text(f, scene);
    fprintf(f, ": %ux%u, %u frames at %u Hz, error against time per displayed frame</text>\n", (unsigned)h->width,
            (unsigned)h->height, (unsigned)h->frames, (unsigned)h->refresh_hz);
    draw_panel(f, rows, n, 0, &ax, methods, nm);
    draw_panel(f, rows, n, 1, &ax, methods, nm);
    for (size_t mi = 0; mi < nm; mi++) {
        double x = PANEL_LEFT0 + (double)(mi % 4) * 230, y = PANEL_TOP + PANEL_H + 62 + 20 * (double)(mi / 4);
        const char *col = palette[mi % (sizeof palette / sizeof palette[0])];
        const char *knob = "";
        for (size_t i = 0; i < n; i++)
            if (!strcmp(rows[i]->method, methods[mi]))
                knob = rows[i]->knob;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"2\"/>\n", x,
                y - 4, x + 24, y - 4, col);
        fprintf(f, "<text class=\"legend\" x=\"%.1f\" y=\"%.1f\" font-size=\"12\">", x + 30, y);
        xml_text(f, methods[mi]);
        fputs(" (", f);
        xml_text(f, knob);
        fputs(")</text>\n", f);
    }
    fprintf(f, "<text x=\"%d\" y=\"%d\" font-size=\"11\" fill=\"#555\" text-anchor=\"end\">ringed: Pareto front "
               "(dashed)</text>\n", SVG_W - 20, height - 8);
    fprintf(f, "</svg>\n");
    return finish(&out, err);
}
