/* The render modes' table (mode.h): one row per hz_render_mode_t, in its order. */
#include "../render/mode.h"

extern const hz_mode_ops_t hz_mode_full, hz_mode_taa, hz_mode_tdense, hz_mode_adaptive;

const hz_mode_ops_t *const hz_render_modes[HZ_MODE_COUNT] = {
    [HZ_MODE_FULL] = &hz_mode_full,
    [HZ_MODE_TAA] = &hz_mode_taa,
    [HZ_MODE_TDENSE] = &hz_mode_tdense,
    [HZ_MODE_ADAPTIVE] = &hz_mode_adaptive,
};
