/* The v-sync model: lock, classification, least-squares period and phase (see hz/vsync.h). */
#include "hz/vsync.h"

#include "hz/tstat.h"
#include "wide.h"

#define Q16 65536

static int64_t q16_to_ns(int64_t q)
{
    /* (q + Q16 / 2) / Q16 without the overflow of q + Q16 / 2 near INT64_MAX (a saturated period). */
    return q >= 0 ? q / Q16 + (q % Q16 >= Q16 / 2) : (q + Q16 / 2) / Q16;
}

/* a + b and a - b saturated to [INT64_MIN + 1, INT64_MAX] like wide.h's helpers: predictions for slots (or
 * times) far from the anchor, near the ends of the range, must not wrap (signed overflow). */
static int64_t sat_add(int64_t a, int64_t b)
{
    if (b > 0 && a > INT64_MAX - b)
        return INT64_MAX;
    if (b < 0 && a < INT64_MIN + 1 - b)
        return INT64_MIN + 1;
    return a + b;
}

static int64_t sat_sub(int64_t a, int64_t b)
{
    return b == INT64_MIN ? sat_add(sat_add(a, INT64_MAX), 1) : sat_add(a, -b);
}

static int64_t predict(const hz_vsync_t *v, int64_t slot)
{
    return sat_add(v->anchor_t, hz_mul_q16(sat_sub(slot, v->anchor_slot), v->period_q16));
}

static int64_t nearest_slot(const hz_vsync_t *v, int64_t t)
{
    return sat_add(v->anchor_slot, hz_muldiv(sat_sub(t, v->anchor_t), Q16, v->period_q16));
}

static void emit(hz_vsync_t *v, const hz_vsync_event_t *ev)
{
    /* Callers drain after every push and one push emits at most HZ_VSYNC_ACQ + 2 events, so the queue never
     * fills in correct use; if it does, the oldest event is overwritten rather than the newest refused. */
    uint32_t at = (v->q_head + v->q_n) % HZ_VSYNC_QUEUE;
    v->queue[at] = *ev;
    if (v->q_n < HZ_VSYNC_QUEUE)
        v->q_n++;
    else
        v->q_head = (v->q_head + 1) % HZ_VSYNC_QUEUE;
}

static void emit_spurious(hz_vsync_t *v, int64_t t, uint64_t index, int64_t slot, int64_t residual, uint8_t why)
{
    hz_vsync_event_t ev = { 0 };
    ev.t_ns = t;
    ev.slot = slot;
    ev.residual_ns = residual;
    ev.index = index;
    ev.kind = HZ_VSYNC_SPURIOUS;
    ev.why = why;
    v->counts.spurious++;
    switch (why) {
    case HZ_VSYNC_WHY_OFFGRID: v->counts.offgrid++; break;
    case HZ_VSYNC_WHY_DUPLICATE: v->counts.duplicate++; break;
    case HZ_VSYNC_WHY_BACKWARDS: v->counts.backwards++; break;
    default: v->counts.nolock++; break;
    }
    emit(v, &ev);
}

static int64_t acq_tol(const hz_vsync_t *v, int64_t p_q16)
{
    int64_t t = q16_to_ns(p_q16) / 8;
    return v->cfg.tol_min_ns > t ? v->cfg.tol_min_ns : t;
}

static int64_t tol_floor(const hz_vsync_t *v)
{
    int64_t p = q16_to_ns(v->period_q16);
    return v->cfg.tol_min_ns > 0 ? v->cfg.tol_min_ns : p / 64;
}

/* Slots the window must span before its slope is trusted: with a known nominal period the slope only has
 * to beat that prior; without one it is all there is. */
static int64_t span_needed(const hz_vsync_t *v)
{
    return v->nominal_q16 > 0 ? HZ_VSYNC_SPAN_FOR_SLOPE : 4;
}

/* v * 2^s, saturated like the helpers above. */
static int64_t sat_shl(int64_t v, int s)
{
    if (hz_abs64(v) > ((uint64_t)INT64_MAX >> s))
        return v < 0 ? INT64_MIN + 1 : INT64_MAX;
    return v < 0 ? -(int64_t)(hz_abs64(v) << s) : (int64_t)((uint64_t)v << s);
}

/* Least squares y = a + b x over the ring entries selected by `use` (NULL: all). x, y are relative to the
 * newest entry and the current period; b comes back in Q16 ns per slot, a in ns.
 *
 * The sums are int64. With m entries, |x| <= X and |y| <= Y they stay below 2^61 while m X <= 2^30,
 * m^2 X Y <= 2^60 and m Y <= 2^46: far beyond a real window (a few thousand slots, microseconds of residual),
 * where nothing below changes a bit. A trace with gaps of years or residuals of hours (a file's timestamps can
 * be anything up to 2^63 ns) first has x and y divided by powers of two until they fit, which loses low bits
 * of an absurd fit instead of overflowing. */
static void fit_line(const int64_t *x, const int64_t *y, const uint8_t *use, uint32_t n, int slope,
                     int64_t *a, int64_t *b_q16)
{
    int64_t m = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    uint64_t mx = 0, my = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (use && !use[i])
            continue;
        m++;
        if (hz_abs64(x[i]) > mx)
            mx = hz_abs64(x[i]);
        if (hz_abs64(y[i]) > my)
            my = hz_abs64(y[i]);
    }
    *a = 0;
    *b_q16 = 0;
    if (m == 0)
        return;
    int shx = 0, shy = 0;
    while ((mx >> shx) > ((uint64_t)1 << 30) / (uint64_t)m)
        shx++;
    uint64_t xs = (mx >> shx) ? (mx >> shx) : 1;
    while ((my >> shy) > ((uint64_t)1 << 60) / ((uint64_t)m * (uint64_t)m) / xs ||
           (my >> shy) > ((uint64_t)1 << 46) / (uint64_t)m)
        shy++;
    int64_t dx = (int64_t)1 << shx, dy = (int64_t)1 << shy;
    for (uint32_t i = 0; i < n; i++) {
        if (use && !use[i])
            continue;
        int64_t xi = x[i] / dx, yi = y[i] / dy;
        sx += xi;
        sy += yi;
        sxx += xi * xi;
        sxy += xi * yi;
    }
    int64_t den = m * sxx - sx * sx;
    if (slope && m >= 2 && den > 0) {
        int64_t b = hz_muldiv(m * sxy - sx * sy, Q16, den), a_s;
        /* sy Q16 < 2^62 by the limits; b sx is exact while it stays below 2^62, else rounded once more. */
        if (hz_abs64(b) <= ((uint64_t)1 << 62) / (hz_abs64(sx) + 1))
            a_s = hz_muldiv(sy * Q16 - b * sx, 1, m * Q16);
        else
            a_s = hz_muldiv(sat_sub(sy, hz_mul_q16(sx, b)), 1, m);
        *a = sat_shl(a_s, shy);
        *b_q16 = shy >= shx ? sat_shl(b, shy - shx) : hz_muldiv(b, 1, (int64_t)1 << (shx - shy));
    } else {
        *a = sat_shl(hz_muldiv(sy, 1, m), shy);
    }
}

static void refit(hz_vsync_t *v)
{
    uint32_t w = v->cfg.window, n = v->ring_n;
    uint32_t newest = (v->ring_next + w - 1) % w, oldest = (v->ring_next + w - n) % w;
    int64_t s_r = v->ring_slot[newest], t_r = v->ring_t[newest];
    int64_t p_ns = q16_to_ns(v->period_q16);
    int64_t span = sat_sub(s_r, v->ring_slot[oldest]);
    int slope = span >= span_needed(v);
    int64_t *x = v->fit_x, *y = v->fit_y, *e = v->fit_e;
    uint8_t *use = v->fit_use;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t at = (oldest + i) % w;
        x[i] = sat_sub(v->ring_slot[at], s_r);
        y[i] = sat_sub(sat_sub(v->ring_t[at], t_r), hz_mul_q16(x[i], v->period_q16));
    }
    int64_t a, b;
    fit_line(x, y, 0, n, slope, &a, &b);
    for (uint32_t i = 0; i < n; i++) {
        e[i] = sat_sub(sat_sub(y[i], a), hz_mul_q16(x[i], b));
        v->scratch[i] = (int64_t)hz_abs64(e[i]);
    }
    int64_t mad = hz_select_i64(v->scratch, n, (n - 1) / 2);
    int64_t thr = mad > INT64_MAX / 6 ? INT64_MAX : (6 * mad > 1000 ? 6 * mad : 1000);
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        use[i] = (int64_t)hz_abs64(e[i]) <= thr;
        kept += use[i];
    }
    if (kept < n && kept >= 2 && 2 * kept >= n)
        fit_line(x, y, use, n, slope, &a, &b);
    v->period_q16 = sat_add(v->period_q16, b);
    if (v->period_q16 < Q16)
        v->period_q16 = Q16; /* a period below 1 ns is nonsense; keep the arithmetic sane */
    v->anchor_slot = s_r;
    v->anchor_t = sat_add(t_r, a);
    v->sigma_ns = mad <= INT64_MAX / 14826 ? mad * 14826 / 10000 : hz_muldiv(mad, 14826, 10000);
    p_ns = q16_to_ns(v->period_q16);
    if (span < HZ_VSYNC_SPAN_FOR_SLOPE) {
        v->tol_ns = acq_tol(v, v->period_q16);
    } else {
        int64_t floor = tol_floor(v), cap = p_ns / 4, tol = v->sigma_ns > INT64_MAX / 8 ? INT64_MAX : 8 * v->sigma_ns;
        if (floor > cap)
            floor = cap;
        v->tol_ns = tol < floor ? floor : (tol > cap ? cap : tol);
    }
}

static void ring_push(hz_vsync_t *v, int64_t slot, int64_t t)
{
    uint32_t w = v->cfg.window;
    v->ring_slot[v->ring_next] = slot;
    v->ring_t[v->ring_next] = t;
    v->ring_next = (v->ring_next + 1) % w;
    if (v->ring_n < w)
        v->ring_n++;
}

static void commit(hz_vsync_t *v, hz_vsync_event_t ev)
{
    ev.missed_before = 0;
    if (v->has_last) {
        int64_t gap = sat_sub(sat_sub(ev.slot, v->last_slot), 1);
        ev.missed_before = gap > 0 ? (gap > UINT32_MAX ? UINT32_MAX : (uint32_t)gap) : 0;
    }
    v->counts.missed += ev.missed_before;
    v->counts.accepted++;
    ring_push(v, ev.slot, ev.t_ns);
    refit(v);
    v->last_slot = ev.slot;
    v->has_last = true;
    emit(v, &ev);
}

static void commit_pending(hz_vsync_t *v)
{
    if (v->has_pending) {
        v->has_pending = false;
        commit(v, v->pending);
    }
}

/* How many buffered edges lie on the grid of period p (Q16) through edge `anchor`, within p/8. */
static uint32_t grid_count(const hz_vsync_t *v, uint32_t anchor, int64_t p_q16)
{
    int64_t tol = acq_tol(v, p_q16);
    uint32_t count = 0;
    for (uint32_t j = 0; j < v->acq_n; j++) {
        int64_t d = sat_sub(v->acq_t[j], v->acq_t[anchor]);
        int64_t k = hz_muldiv(d, Q16, p_q16);
        if ((int64_t)hz_abs64(sat_sub(d, hz_mul_q16(k, p_q16))) <= tol)
            count++;
    }
    return count;
}

/* Tries to lock on the acquisition buffer. `final`: no more edges will come. */
static void acquire(hz_vsync_t *v, int final)
{
    uint32_t n = v->acq_n;
    if (n == 0)
        return;
    /* Candidate periods: what the model last knew (or the nominal one), and the median interval. */
    int64_t cand[2];
    int ncand = 0;
    if (v->period_q16 > 0)
        cand[ncand++] = v->period_q16;
    else if (v->nominal_q16 > 0)
        cand[ncand++] = v->nominal_q16;
    if (n >= 4) {
        for (uint32_t i = 1; i < n; i++)
            v->scratch[i - 1] = sat_sub(v->acq_t[i], v->acq_t[i - 1]);
        int64_t med = hz_select_i64(v->scratch, n - 1, (n - 2) / 2);
        if (med > 0 && med < INT64_MAX / Q16)
            cand[ncand++] = med * Q16;
    }
    uint32_t best = 0, best_anchor = 0;
    int64_t best_p = 0;
    for (int c = 0; c < ncand; c++)
        for (uint32_t i = 0; i < n; i++) {
            uint32_t cnt = grid_count(v, i, cand[c]);
            if (cnt > best) {
                best = cnt;
                best_anchor = i;
                best_p = cand[c];
            }
        }
    uint32_t need = n / 2 + 1;
    if (need < 3)
        need = 3;
    if (best < need || n < 2) {
        if (!final) {
            emit_spurious(v, v->acq_t[0], v->acq_index[0], 0, 0, HZ_VSYNC_WHY_NOLOCK);
            for (uint32_t i = 1; i < n; i++) {
                v->acq_t[i - 1] = v->acq_t[i];
                v->acq_index[i - 1] = v->acq_index[i];
            }
            v->acq_n--;
        } else {
            for (uint32_t i = 0; i < n; i++)
                emit_spurious(v, v->acq_t[i], v->acq_index[i], 0, 0, HZ_VSYNC_WHY_NOLOCK);
            v->acq_n = 0;
        }
        return;
    }
    /* Grid index and residual of every buffered edge; of two edges on one grid point keep the nearer. */
    int64_t k[HZ_VSYNC_ACQ], r[HZ_VSYNC_ACQ];
    uint8_t in[HZ_VSYNC_ACQ];
    int64_t tol = acq_tol(v, best_p);
    for (uint32_t j = 0; j < n; j++) {
        int64_t d = sat_sub(v->acq_t[j], v->acq_t[best_anchor]);
        k[j] = hz_muldiv(d, Q16, best_p);
        r[j] = sat_sub(d, hz_mul_q16(k[j], best_p));
        in[j] = (int64_t)hz_abs64(r[j]) <= tol;
    }
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n && in[j]; i++)
            if (i != j && in[i] && k[i] == k[j] &&
                (hz_abs64(r[i]) < hz_abs64(r[j]) || (hz_abs64(r[i]) == hz_abs64(r[j]) && i < j)))
                in[j] = 0;
    uint32_t first = n, last = 0;
    for (uint32_t j = 0; j < n; j++)
        if (in[j]) {
            if (first == n)
                first = j;
            last = j;
        }
    /* Slot numbering stays continuous across a relock: the old model places the first new edge. */
    int64_t base = 0;
    if (v->ever_locked && v->period_q16 > 0) {
        base = nearest_slot(v, v->acq_t[first]);
        if (v->has_last && base <= v->last_slot)
            base = sat_add(v->last_slot, 1);
    }
    int relock = v->ever_locked;
    v->period_q16 = best_p;
    v->anchor_slot = base;
    v->anchor_t = v->acq_t[first];
    v->ring_n = v->ring_next = 0;
    v->tol_ns = tol;
    v->locked = v->ever_locked = true;
    v->rejects_in_row = 0;
    if (relock)
        v->counts.relocks++;
    for (uint32_t j = 0; j < n; j++) {
        int64_t slot = sat_add(base, sat_sub(k[j], k[first]));
        if (!in[j]) {
            emit_spurious(v, v->acq_t[j], v->acq_index[j], slot, sat_sub(v->acq_t[j], predict(v, slot)),
                          (int64_t)hz_abs64(r[j]) <= tol ? HZ_VSYNC_WHY_DUPLICATE : HZ_VSYNC_WHY_OFFGRID);
            continue;
        }
        hz_vsync_event_t ev = { 0 };
        ev.t_ns = v->acq_t[j];
        ev.slot = slot;
        ev.residual_ns = sat_sub(v->acq_t[j], predict(v, slot));
        ev.index = v->acq_index[j];
        ev.kind = HZ_VSYNC_EDGE;
        ev.relock = (uint8_t)(relock && j == first);
        if (j == last) {
            v->pending = ev;
            v->has_pending = true;
        } else {
            commit(v, ev);
        }
    }
    v->acq_n = 0;
}

hz_status_t hz_vsync_init(hz_vsync_t *v, const hz_vsync_cfg_t *cfg, hz_error_t *err)
{
    hz_vsync_cfg_t c = *cfg;
    if (c.window == 0)
        c.window = HZ_VSYNC_WINDOW_DEFAULT;
    if (c.window < 8 || c.window > HZ_VSYNC_WINDOW_MAX)
        return hz_error_set(err, HZ_E_INVALID_ARG, "v-sync model: window of %u edges is outside [8, %u]",
                            c.window, (unsigned)HZ_VSYNC_WINDOW_MAX);
    if (c.nominal_period_ns < 0 || c.nominal_period_ns > 10000000000ll)
        return hz_error_set(err, HZ_E_INVALID_ARG,
                            "v-sync model: nominal period %lld ns is outside [0, 10 s] (0 = learn it)",
                            (long long)c.nominal_period_ns);
    if (c.tol_min_ns < 0)
        return hz_error_set(err, HZ_E_INVALID_ARG, "v-sync model: negative tolerance %lld ns",
                            (long long)c.tol_min_ns);
    hz_vsync_t zero = { 0 };
    *v = zero;
    v->cfg = c;
    v->nominal_q16 = c.nominal_period_ns * Q16;
    return HZ_OK;
}

void hz_vsync_push(hz_vsync_t *v, int64_t t)
{
    uint64_t index = v->counts.inputs++;
    if (v->any_input && t <= v->last_input_t) {
        emit_spurious(v, t, index, v->locked ? nearest_slot(v, t) : 0, 0, HZ_VSYNC_WHY_BACKWARDS);
        return;
    }
    v->any_input = true;
    v->last_input_t = t;
    if (!v->locked) {
        v->acq_t[v->acq_n] = t;
        v->acq_index[v->acq_n] = index;
        if (++v->acq_n == HZ_VSYNC_ACQ)
            acquire(v, 0);
        return;
    }
    int64_t k = nearest_slot(v, t);
    if (v->has_pending && k > v->pending.slot) {
        commit_pending(v);
        k = nearest_slot(v, t);
    }
    int64_t r = sat_sub(t, predict(v, k));
    if ((int64_t)hz_abs64(r) > v->tol_ns) {
        emit_spurious(v, t, index, k, r, HZ_VSYNC_WHY_OFFGRID);
        if (++v->rejects_in_row >= HZ_VSYNC_RELOCK) {
            commit_pending(v);
            v->locked = false;
            v->acq_n = 0;
            v->rejects_in_row = 0;
        }
        return;
    }
    v->rejects_in_row = 0;
    if (v->has_last && k <= v->last_slot) {
        emit_spurious(v, t, index, k, r, HZ_VSYNC_WHY_DUPLICATE);
        return;
    }
    hz_vsync_event_t ev = { 0 };
    ev.t_ns = t;
    ev.slot = k;
    ev.residual_ns = r;
    ev.index = index;
    ev.kind = HZ_VSYNC_EDGE;
    if (v->has_pending && k < v->pending.slot) {
        /* Later than the tentative edge yet nearer an earlier slot: cannot be that slot's edge. */
        emit_spurious(v, t, index, k, r, HZ_VSYNC_WHY_DUPLICATE);
        return;
    }
    if (v->has_pending && k == v->pending.slot) {
        if (hz_abs64(r) < hz_abs64(v->pending.residual_ns)) {
            emit_spurious(v, v->pending.t_ns, v->pending.index, k, v->pending.residual_ns,
                          HZ_VSYNC_WHY_DUPLICATE);
            v->pending = ev;
        } else {
            emit_spurious(v, t, index, k, r, HZ_VSYNC_WHY_DUPLICATE);
        }
        return;
    }
    v->pending = ev;
    v->has_pending = true;
}

void hz_vsync_flush(hz_vsync_t *v)
{
    if (!v->locked)
        acquire(v, 1);
    commit_pending(v);
}

bool hz_vsync_pop(hz_vsync_t *v, hz_vsync_event_t *ev)
{
    if (v->q_n == 0)
        return false;
    *ev = v->queue[v->q_head];
    v->q_head = (v->q_head + 1) % HZ_VSYNC_QUEUE;
    v->q_n--;
    return true;
}

bool hz_vsync_locked(const hz_vsync_t *v)
{
    return v->locked && v->has_last;
}

int64_t hz_vsync_period_q16(const hz_vsync_t *v)
{
    return v->ever_locked ? v->period_q16 : 0;
}

int64_t hz_vsync_period_ns(const hz_vsync_t *v)
{
    return v->ever_locked ? q16_to_ns(v->period_q16) : 0;
}

int64_t hz_vsync_slot_time(const hz_vsync_t *v, int64_t slot)
{
    return predict(v, slot);
}

int64_t hz_vsync_slot_at_or_after(const hz_vsync_t *v, int64_t t)
{
    /* Without a period (no lock yet) every slot predicts the same time: there is no answer to search for
     * (the loops below never ended). */
    if (v->period_q16 <= 0)
        return v->anchor_slot;
    int64_t k = nearest_slot(v, t);
    /* nearest_slot is within one slot of the answer; predictions saturate at the ends of the int64 range, where
     * they stop increasing, so the corrections are bounded rather than run until a saturated prediction
     * passes t (forever for t = INT64_MIN) or k wraps. */
    for (int i = 0; i < 4 && k < INT64_MAX && predict(v, k) < t; i++)
        k++;
    for (int i = 0; i < 4 && k > INT64_MIN + 1 && predict(v, k - 1) >= t; i++)
        k--;
    return k;
}

int64_t hz_vsync_tolerance_ns(const hz_vsync_t *v)
{
    return v->tol_ns;
}

int64_t hz_vsync_sigma_ns(const hz_vsync_t *v)
{
    return v->sigma_ns;
}

int64_t hz_vsync_offset_ppb(const hz_vsync_t *v)
{
    if (v->nominal_q16 <= 0 || !v->ever_locked)
        return 0;
    return hz_muldiv(v->period_q16 - v->nominal_q16, 1000000000, v->nominal_q16);
}

const hz_vsync_counts_t *hz_vsync_counts(const hz_vsync_t *v)
{
    return &v->counts;
}

int64_t hz_vsync_period_q16_from_mhz(uint64_t millihertz)
{
    if (millihertz == 0)
        return 0;
    return hz_muldiv(1000000000000ll, Q16, (int64_t)millihertz);
}
