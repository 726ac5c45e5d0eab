/* The --transparency option's text form (see transp_opt.h). */
#include "transp_opt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool hz_transp_parse(const char *s, hz_transp_t *method, float *hybrid_x)
{
    if (!s)
        return false;
    if (!strncmp(s, "hybrid:", 7)) {
        const char *v = s + 7;
        char *end = NULL;
        if (!*v || !strchr("0123456789.", *v))
            return false;
        double x = strtod(v, &end);
        if (*end || !isfinite(x) || x < 0.0 || x > 1.0)
            return false;
        *method = HZ_TRANSP_HYBRID;
        *hybrid_x = (float)x;
        return true;
    }
    for (int t = 0; t < HZ_TRANSP_COUNT; t++)
        if (t != HZ_TRANSP_HYBRID && !strcmp(s, hz_transp_name((hz_transp_t)t))) {
            *method = (hz_transp_t)t;
            return true;
        }
    return false;
}

void hz_transp_format(char *buf, size_t size, hz_transp_t method, float hybrid_x)
{
    if (method == HZ_TRANSP_HYBRID)
        snprintf(buf, size, "hybrid:%g", (double)hybrid_x);
    else
        snprintf(buf, size, "%s", hz_transp_name(method));
}
