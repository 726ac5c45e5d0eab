/* Backend choice for the Linux port (see accel_backend.h). */
#include "accel_backend.h"

#if HZ_HAVE_EMBREE
#include "embree_accel.h"
#endif

const char *hz_accel_backend_name(hz_accel_backend_t backend)
{
    return backend == HZ_ACCEL_EMBREE ? "embree" : "native";
}

hz_status_t hz_accel_backend_build(hz_accel_backend_t backend, hz_accel_t **out, const hz_accel_geom_t *geom,
                                   hz_arena_t *arena, hz_error_t *err)
{
    return hz_accel_backend_build_cfg(backend, out, geom, NULL, arena, err);
}

hz_status_t hz_accel_backend_build_cfg(hz_accel_backend_t backend, hz_accel_t **out, const hz_accel_geom_t *geom,
                                       const hz_accel_config_t *cfg, hz_arena_t *arena, hz_error_t *err)
{
    if (backend == HZ_ACCEL_NATIVE)
        return hz_accel_build_native(out, geom, cfg, arena, err);
#if HZ_HAVE_EMBREE
    return hz_accel_build_embree(out, geom, NULL, NULL, arena, err);
#else
    (void)cfg;
    return hz_error_set(err, HZ_E_UNSUPPORTED, "board %s is built without the Embree backend (use --backend native)",
                        HZ_BOARD_NAME);
#endif
}
