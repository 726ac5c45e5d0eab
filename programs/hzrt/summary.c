/* Run summary: text and JSON (see summary.h). */
#include "summary.h"

#include "fileio.h"

static size_t thread_high_water(const hz_pools_t *p, int threads)
{
    size_t m = 0;
    for (int i = 0; i < threads; i++)
        if (p->thread[i].high_water > m)
            m = p->thread[i].high_water;
    return m;
}

void hz_summary_print(const hz_summary_t *s, FILE *f)
{
    const hz_pools_t *p = s->pools;
    fprintf(f, "scene        %s  [%s]\n", s->scene, s->features);
    fprintf(f, "render       %ux%u, mode %s, %g spp per frame, %d threads, backend %s (built in %.1f ms)\n",
            s->width, s->height, s->mode, s->spp, s->threads, s->backend, s->build_ms);
    for (int i = 0; i < s->n_notes; i++)
        fprintf(f, "note         %s\n", s->notes[i]);
    if (s->interrupted)
        fprintf(f, "interrupted  by %s: the frames finished so far are kept\n", s->interrupted);
    fprintf(f, "frames       %u at a simulated %u Hz, scene time %.4g to %.4g s\n", s->frames, s->hz, (double)s->start,
            (double)s->start + (double)(s->frames ? s->frames - 1 : 0) / s->hz);
    fprintf(f, "frame time   p50 %.3f ms, p99 %.3f ms, mean %.3f ms, max %.3f ms (%u frame%s timed)\n", s->ms_p50,
            s->ms_p99, s->ms_mean, s->ms_max, s->frames_timed, s->frames_timed == 1 ? "" : "s");
    double nf = s->frames ? (double)s->frames : 1.0;
    fprintf(f, "rays         %.0f per frame (primary %.0f, shadow %.0f, secondary %.0f), %llu in total, %.2f Mrays/s\n",
            s->rays_per_frame, s->stats.primary_rays / nf, s->stats.shadow_rays / nf, s->stats.secondary_rays / nf,
            (unsigned long long)s->rays, s->mrays_per_s);
    fprintf(f, "memory       scene %.1f / %.0f MiB, accel %.1f / %.0f MiB, frame %.1f / %.0f MiB, thread %.2f / %.0f MiB\n",
            p->scene.high_water / 1048576.0, p->scene.cap / 1048576.0, p->accel.high_water / 1048576.0,
            p->accel.cap / 1048576.0, p->frame.high_water / 1048576.0, p->frame.cap / 1048576.0,
            thread_high_water(p, s->threads) / 1048576.0, p->thread[0].cap / 1048576.0);
    if (s->adaptive)
        fprintf(f, "adaptive     %.3f extra rays/px: %.3f camera rays/px = %.1f%% of fixed 9 spp; %.1f%% of subpixels "
                   "active, %.2f live lanes per extra packet, attributes %u B/px\n",
                s->adaptive->extra_rays_per_pixel, s->adaptive->rays_per_pixel, 100.0 * s->adaptive->sample_ratio_9spp,
                100.0 * s->adaptive->active_fraction, s->adaptive->lanes_per_packet, s->adaptive->attr_bytes_per_pixel);
    if (s->shutter > 0)
        fprintf(f, "motion blur  shutter %.3g of each 1/%u s frame, %s, %u time key%s, %u refit%s, %u rebuild%s\n",
                s->shutter, s->hz, s->blur_accel, s->time_keys, s->time_keys == 1 ? "" : "s", s->refits,
                s->refits == 1 ? "" : "s", s->rebuilds, s->rebuilds == 1 ? "" : "s");
    if (s->shutter > 0 && s->key_sets && s->nodes)
        fprintf(f, "             %s motion segments: %.2f key box sets per node of %u keys\n", s->segments,
                (double)s->key_sets / (double)s->nodes, s->time_keys);
    if (s->shutter > 0 && s->instances)
        fprintf(f, "             %u rigid instance%s (%u triangles) in object space, never refitted\n", s->instances,
                s->instances == 1 ? "" : "s", s->instance_tris);
    if (s->stats.nonfinite || s->stats.layer_cap || s->stats.queue_full)
        fprintf(f, "warnings     %llu non-finite values zeroed, %llu paths cut at the layer cap, %llu rays dropped\n",
                (unsigned long long)s->stats.nonfinite, (unsigned long long)s->stats.layer_cap,
                (unsigned long long)s->stats.queue_full);
}

/* JSON string with the characters JSON requires escaped. */
static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

hz_status_t hz_summary_write_json(const hz_summary_t *s, const char *path, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t st = hz_out_open(&out, path, err);
    if (st != HZ_OK)
        return st;
    FILE *f = out.f;
    const hz_pools_t *p = s->pools;
    fprintf(f, "{\n  \"scene\": ");
    json_str(f, s->scene);
    fprintf(f, ",\n  \"features\": ");
    json_str(f, s->features);
    fprintf(f, ",\n  \"mode\": ");
    json_str(f, s->mode);
    fprintf(f, ",\n  \"backend\": ");
    json_str(f, s->backend);
    fprintf(f, ",\n  \"board\": ");
    json_str(f, HZ_BOARD_NAME);
    fprintf(f, ",\n  \"notes\": [");
    for (int i = 0; i < s->n_notes; i++) {
        fputs(i ? ", " : "", f);
        json_str(f, s->notes[i]);
    }
    fprintf(f, "],\n  \"interrupted\": ");
    if (s->interrupted)
        json_str(f, s->interrupted);
    else
        fputs("false", f);
    fprintf(f, ",\n  \"settings\": {%s}", s->settings ? s->settings : "");
    fprintf(f, ",\n  \"width\": %u, \"height\": %u, \"spp\": %.6g, \"hz\": %u, \"threads\": %d, \"start\": %.6g,\n",
            s->width, s->height, s->spp, s->hz, s->threads, (double)s->start);
    fprintf(f, "  \"frames\": %u, \"frames_timed\": %u, \"run_s\": %.6f, \"accel_build_ms\": %.3f,\n", s->frames,
            s->frames_timed, s->run_s, s->build_ms);
    fprintf(f, "  \"frame_ms\": {\"p50\": %.4f, \"p99\": %.4f, \"mean\": %.4f, \"max\": %.4f},\n", s->ms_p50,
            s->ms_p99, s->ms_mean, s->ms_max);
    double nf = s->frames ? (double)s->frames : 1.0;
    fprintf(f, "  \"rays\": {\"total\": %llu, \"primary\": %llu, \"shadow\": %llu, \"secondary\": %llu, "
               "\"mrays_per_s\": %.3f},\n",
            (unsigned long long)s->rays, (unsigned long long)s->stats.primary_rays,
            (unsigned long long)s->stats.shadow_rays, (unsigned long long)s->stats.secondary_rays, s->mrays_per_s);
    fprintf(f, "  \"rays_per_frame\": {\"total\": %.1f, \"primary\": %.1f, \"shadow\": %.1f, \"secondary\": %.1f},\n",
            s->rays_per_frame, s->stats.primary_rays / nf, s->stats.shadow_rays / nf, s->stats.secondary_rays / nf);
    if (s->shutter > 0) {
        fprintf(f, "  \"motion_blur\": {\"shutter\": %.6g, \"accel\": ", s->shutter);
        json_str(f, s->blur_accel);
        fprintf(f, ", \"time_keys\": %u, \"refits\": %u, \"rebuilds\": %u, \"instances\": %u, \"instance_tris\": %u, "
                   "\"key_sets\": %llu, \"nodes\": %u},\n",
                s->time_keys, s->refits, s->rebuilds, s->instances, s->instance_tris, (unsigned long long)s->key_sets,
                s->nodes);
    }
    fprintf(f, "  \"arenas\": {\"scene\": [%zu, %zu], \"accel\": [%zu, %zu], \"frame\": [%zu, %zu], "
               "\"thread\": [%zu, %zu]},\n",
            p->scene.high_water, p->scene.cap, p->accel.high_water, p->accel.cap, p->frame.high_water, p->frame.cap,
            thread_high_water(p, s->threads), p->thread[0].cap);
    if (s->adaptive)
        fprintf(f, "  \"adaptive\": {\"extra_rays_per_pixel\": %.6f, \"rays_per_pixel\": %.6f, "
                   "\"sample_ratio_9spp\": %.6f, \"active_subpixel_fraction\": %.6f, \"lanes_per_packet\": %.4f, "
                   "\"attribute_bytes_per_pixel\": %u},\n",
                s->adaptive->extra_rays_per_pixel, s->adaptive->rays_per_pixel, s->adaptive->sample_ratio_9spp,
                s->adaptive->active_fraction, s->adaptive->lanes_per_packet, s->adaptive->attr_bytes_per_pixel);
    fprintf(f, "  \"warnings\": {\"nonfinite\": %llu, \"layer_cap\": %llu, \"queue_full\": %llu}\n}\n",
            (unsigned long long)s->stats.nonfinite, (unsigned long long)s->stats.layer_cap,
            (unsigned long long)s->stats.queue_full);
    return hz_out_commit(&out, err);
}
