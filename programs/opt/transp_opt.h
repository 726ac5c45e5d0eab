/*
 * transp_opt.h — the --transparency option's text form, shared by hzrt render, hzbench and hzerrtime:
 * exact | rr | std | dtaa | dtaa-star | hybrid:X (X a number in [0, 1]: exact compositing while the path's
 * visibility is above X, then one STD decision).
 *
 * Contract: hz_transp_parse accepts exactly those forms (X as a plain decimal, e.g. 0.25 or 1) and leaves the
 * outputs untouched on failure; hz_transp_format writes the canonical form ("hybrid:0.25"), which
 * hz_transp_parse reads back to the same method and threshold.
 */
#ifndef HZ_PORT_TRANSP_OPT_H
#define HZ_PORT_TRANSP_OPT_H

#include <stdbool.h>
#include <stddef.h>

#include "hz/dither.h"

bool hz_transp_parse(const char *s, hz_transp_t *method, float *hybrid_x);
void hz_transp_format(char *buf, size_t size, hz_transp_t method, float hybrid_x);

#endif
