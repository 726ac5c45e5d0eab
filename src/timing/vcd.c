/* Streaming single-wire VCD reader (see hz/traceio.h). */
#include "hz/traceio.h"

enum { SEC_NONE = 0, SEC_SKIP, SEC_TIMESCALE, SEC_SCOPE, SEC_VAR, SEC_ENDDEFS, SEC_DUMP };

static int streq(const char *a, const char *b)
{
    while (*a && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}

static size_t slen(const char *s)
{
    size_t n = 0;
    while (s[n])
        n++;
    return n;
}

/* Copies src into dst[cap]; false (dst untouched) when it does not fit. */
static int scopy(char *dst, size_t cap, const char *src)
{
    size_t n = slen(src);
    if (n >= cap)
        return 0;
    for (size_t i = 0; i <= n; i++)
        dst[i] = src[i];
    return 1;
}

hz_status_t hz_vcd_init(hz_vcd_t *p, const char *signal, hz_error_t *err)
{
    hz_vcd_t zero = { 0 };
    *p = zero;
    p->line = 1;
    p->level = -1;
    if (!scopy(p->want, sizeof p->want, signal ? signal : ""))
        return hz_error_set(err, HZ_E_INVALID_ARG, "signal name '%s' is longer than %u characters", signal,
                            (unsigned)sizeof p->want - 1);
    return HZ_OK;
}

static hz_status_t fail(hz_vcd_t *p, hz_error_t *err, hz_status_t code, const char *what, const char *tok)
{
    return hz_error_set(err, code, "line %llu: %s%s%s%s", (unsigned long long)p->tok_line, what,
                        tok ? " '" : "", tok ? tok : "", tok ? "'" : "");
}

/* Parses an unsigned decimal; false on anything else or overflow. */
static int parse_u64(const char *s, uint64_t *out)
{
    uint64_t v = 0;
    if (!*s)
        return 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9')
            return 0;
        uint64_t d = (uint64_t)(*s - '0');
        if (v > (UINT64_MAX - d) / 10)
            return 0;
        v = v * 10 + d;
    }
    *out = v;
    return 1;
}

static hz_status_t end_timescale(hz_vcd_t *p, hz_error_t *err)
{
    /* "1ns" or "1 ns" */
    char buf[HZ_VCD_TOKEN_MAX / 2];
    buf[0] = '\0';
    if (p->sec_arg < 1 || p->sec_arg > 2)
        return fail(p, err, HZ_E_FORMAT, "$timescale needs a value like '1 ns'", 0);
    size_t n = 0;
    for (int i = 0; i < p->sec_arg; i++)
        for (const char *c = p->sec_tok[i]; *c && n + 1 < sizeof buf; c++)
            buf[n++] = *c;
    buf[n] = '\0';
    size_t digits = 0;
    int64_t num = 0;
    while (buf[digits] >= '0' && buf[digits] <= '9' && digits < 4)
        num = num * 10 + (buf[digits++] - '0');
    const char *unit = buf + digits;
    if (num != 1 && num != 10 && num != 100)
        return fail(p, err, HZ_E_FORMAT, "$timescale multiplier must be 1, 10 or 100 in", buf);
    int64_t mul, div = 1;
    if (streq(unit, "s"))
        mul = 1000000000;
    else if (streq(unit, "ms"))
        mul = 1000000;
    else if (streq(unit, "us"))
        mul = 1000;
    else if (streq(unit, "ns"))
        mul = 1;
    else if (streq(unit, "ps")) {
        mul = 1;
        div = 1000;
    } else if (streq(unit, "fs")) {
        mul = 1;
        div = 1000000;
    } else
        return fail(p, err, HZ_E_FORMAT, "$timescale unit must be s, ms, us, ns, ps or fs in", buf);
    p->mul = mul * num;
    p->div = div;
    p->have_timescale = 1;
    return HZ_OK;
}

static void add_name(hz_vcd_t *p, const char *name)
{
    size_t n = slen(p->names), m = slen(name);
    if (n + m + 3 >= sizeof p->names)
        return; /* the message lists as many as fit */
    if (n) {
        p->names[n++] = ',';
        p->names[n++] = ' ';
    }
    for (size_t i = 0; i <= m; i++)
        p->names[n + i] = name[i];
}

static hz_status_t end_var(hz_vcd_t *p, hz_error_t *err)
{
    /* $var type size id reference [bit range] $end */
    if (p->sec_arg < 4)
        return fail(p, err, HZ_E_FORMAT, "$var needs type, size, identifier and name", 0);
    if (!streq(p->sec_tok[1], "1"))
        return HZ_OK; /* buses and reals are not v-sync wires */
    const char *id = p->sec_tok[2], *name = p->sec_tok[3];
    if (p->one_bit_vars++ == 0)
        scopy(p->first_id, sizeof p->first_id, id);
    add_name(p, name);
    if (p->want[0] && streq(name, p->want) && !p->have_id) {
        scopy(p->id, sizeof p->id, id);
        p->have_id = 1;
    }
    return HZ_OK;
}

static hz_status_t end_definitions(hz_vcd_t *p, hz_error_t *err)
{
    if (!p->have_timescale)
        return fail(p, err, HZ_E_FORMAT, "no $timescale before $enddefinitions", 0);
    if (p->want[0]) {
        if (!p->have_id)
            return hz_error_set(err, HZ_E_FORMAT, "line %llu: no 1-bit signal named '%s' (the file has: %s)",
                                (unsigned long long)p->tok_line, p->want, p->names[0] ? p->names : "none");
    } else if (p->one_bit_vars == 1) {
        scopy(p->id, sizeof p->id, p->first_id);
        p->have_id = 1;
    } else if (p->one_bit_vars == 0) {
        return fail(p, err, HZ_E_FORMAT, "the file declares no 1-bit signal", 0);
    } else {
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: %d 1-bit signals (%s): name the v-sync one",
                            (unsigned long long)p->tok_line, p->one_bit_vars, p->names);
    }
    p->in_body = 1;
    return HZ_OK;
}

static hz_status_t change(hz_vcd_t *p, const char *id, int level, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    if (!*id)
        return fail(p, err, HZ_E_FORMAT, "value change without an identifier", 0);
    if (!streq(id, p->id))
        return HZ_OK;
    p->changes++;
    int prev = p->level;
    p->level = level;
    if (prev < 0 || level < 0 || prev == level)
        return HZ_OK;
    /* ticks * mul / div, rounded; the overflow was ruled out when the time was read. */
    uint64_t t = (p->ticks * (uint64_t)p->mul + (uint64_t)p->div / 2) / (uint64_t)p->div;
    p->edges++;
    return edge(ctx, (int64_t)t, level, err);
}

static int value_level(char c)
{
    return c == '1' ? 1 : c == '0' ? 0 : -1;
}

static hz_status_t token(hz_vcd_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    const char *t = p->tok;
    if (p->section == SEC_SKIP) {
        if (!p->tok_long && streq(t, "$end"))
            p->section = SEC_NONE;
        return HZ_OK;
    }
    if (p->tok_long)
        return fail(p, err, HZ_E_FORMAT, "token longer than 255 characters", 0);
    /* Identifier codes are any printable characters, '$' included (sigrok names its fourth channel "$"):
     * the third and fourth fields of a $var (code, name) and the token after a vector or real value are identifiers, whatever they
     * start with. Only a lone "$end" there is read as the end of the section. */
    if (p->section == SEC_VAR && (p->sec_arg == 2 || p->sec_arg == 3) && !streq(t, "$end")) {
        if (!scopy(p->sec_tok[p->sec_arg], sizeof p->sec_tok[0], t))
            return fail(p, err, HZ_E_FORMAT, "identifier code or name longer than 255 characters", 0);
        p->sec_arg++;
        return HZ_OK;
    }
    if (p->pending_vector && p->in_body) {
        p->pending_vector = 0;
        return change(p, t, p->vector_level, edge, ctx, err);
    }
    if (t[0] == '$') {
        if (streq(t, "$end")) {
            hz_status_t s = HZ_OK;
            switch (p->section) {
            case SEC_NONE: return fail(p, err, HZ_E_FORMAT, "$end without a section", 0);
            case SEC_TIMESCALE: s = end_timescale(p, err); break;
            case SEC_VAR: s = end_var(p, err); break;
            case SEC_ENDDEFS: s = end_definitions(p, err); break;
            default: break;
            }
            p->section = SEC_NONE;
            return s;
        }
        if (p->section != SEC_NONE)
            return hz_error_set(err, HZ_E_FORMAT, "line %llu: '%s' inside %s (missing $end?)",
                                (unsigned long long)p->tok_line, t, p->sec_kw);
        p->sec_arg = 0;
        if (!scopy(p->sec_kw, sizeof p->sec_kw, t))
            scopy(p->sec_kw, sizeof p->sec_kw, "a $section");
        if (streq(t, "$timescale") || streq(t, "$var") || streq(t, "$scope") || streq(t, "$upscope") ||
            streq(t, "$enddefinitions")) {
            if (p->in_body)
                return fail(p, err, HZ_E_FORMAT, "declaration after $enddefinitions:", t);
            p->section = streq(t, "$timescale") ? SEC_TIMESCALE
                         : streq(t, "$var")     ? SEC_VAR
                         : streq(t, "$enddefinitions") ? SEC_ENDDEFS
                                                       : SEC_SCOPE;
        } else if (streq(t, "$dumpvars") || streq(t, "$dumpall") || streq(t, "$dumpon") || streq(t, "$dumpoff")) {
            if (!p->in_body)
                return fail(p, err, HZ_E_FORMAT, "value dump before $enddefinitions:", t);
            p->section = SEC_DUMP;
        } else {
            p->section = SEC_SKIP; /* $date, $version, $comment and vendor extensions */
        }
        return HZ_OK;
    }
    if (p->section != SEC_NONE && p->section != SEC_DUMP) {
        if (p->sec_arg < 4 && !scopy(p->sec_tok[p->sec_arg], sizeof p->sec_tok[0], t))
            return fail(p, err, HZ_E_FORMAT, "declaration field longer than 255 characters", 0);
        p->sec_arg++;
        return HZ_OK;
    }
    if (!p->in_body)
        return fail(p, err, HZ_E_FORMAT, "value change before $enddefinitions:", t);
    switch (t[0]) {
    case '#': {
        uint64_t ticks;
        if (!parse_u64(t + 1, &ticks))
            return fail(p, err, HZ_E_FORMAT, "bad timestamp", t);
        if (p->have_time && ticks < p->ticks)
            return fail(p, err, HZ_E_FORMAT, "time goes backwards at", t);
        if (ticks > (uint64_t)INT64_MAX / (uint64_t)p->mul)
            return fail(p, err, HZ_E_RANGE, "time does not fit 64-bit nanoseconds:", t);
        p->ticks = ticks;
        p->have_time = 1;
        return HZ_OK;
    }
    case '0': case '1': case 'x': case 'X': case 'z': case 'Z':
        return change(p, t + 1, value_level(t[0]), edge, ctx, err);
    case 'b': case 'B': {
        /* A vector value; for a 1-bit signal its last digit is the level. */
        size_t n = slen(t);
        if (n < 2)
            return fail(p, err, HZ_E_FORMAT, "empty vector value", t);
        for (size_t i = 1; i < n; i++)
            if (value_level(t[i]) < 0 && t[i] != 'x' && t[i] != 'X' && t[i] != 'z' && t[i] != 'Z')
                return fail(p, err, HZ_E_FORMAT, "bad vector value", t);
        p->vector_level = value_level(t[n - 1]);
        p->pending_vector = 1;
        return HZ_OK;
    }
    case 'r': case 'R':
        p->vector_level = -1;
        p->pending_vector = 1;
        return HZ_OK;
    default:
        return fail(p, err, HZ_E_FORMAT, "not a value change or #time:", t);
    }
}

static hz_status_t end_token(hz_vcd_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    if (p->tok_len == 0 && !p->tok_long)
        return HZ_OK;
    p->tok[p->tok_len] = '\0';
    hz_status_t s = token(p, edge, ctx, err);
    p->tok_len = 0;
    p->tok_long = 0;
    return s;
}

hz_status_t hz_vcd_feed(hz_vcd_t *p, const char *data, size_t n, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)data[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f') {
            hz_status_t s = end_token(p, edge, ctx, err);
            if (s != HZ_OK)
                return s;
            if (c == '\n')
                p->line++;
            continue;
        }
        if ((c < 0x20 || c >= 0x7f) && p->section != SEC_SKIP) {
            p->tok_line = p->line;
            return hz_error_set(err, HZ_E_FORMAT, "line %llu: byte 0x%02x is not VCD text",
                                (unsigned long long)p->line, c);
        }
        if (p->tok_len == 0 && !p->tok_long)
            p->tok_line = p->line;
        if (p->tok_len + 1 < sizeof p->tok)
            p->tok[p->tok_len++] = (char)c;
        else
            p->tok_long = 1;
    }
    return HZ_OK;
}

hz_status_t hz_vcd_finish(hz_vcd_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err)
{
    hz_status_t s = end_token(p, edge, ctx, err);
    if (s != HZ_OK)
        return s;
    p->tok_line = p->line;
    if (p->section != SEC_NONE)
        return hz_error_set(err, HZ_E_FORMAT, "line %llu: the file ends inside %s (missing $end)",
                            (unsigned long long)p->line, p->sec_kw);
    if (p->pending_vector)
        return fail(p, err, HZ_E_FORMAT, "the file ends after a vector value without its identifier", 0);
    if (!p->in_body)
        return fail(p, err, HZ_E_FORMAT, "no $enddefinitions: not a VCD trace, or cut short", 0);
    return HZ_OK;
}
