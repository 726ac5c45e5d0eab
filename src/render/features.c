/* What a scene and the render options need of the features a board can compile out (hz/config.h), against what
 * this build has: a request for a feature that is left out is refused by name, never rendered without it. */
#include "hz/render.h"
#include "render_internal.h"

/* The boards whose board.h has each feature (the Makefile lists them; other builds, such as the host tools,
 * do not). */
#ifndef HZ_FEATURE_BOARDS_TEXTURES
#define HZ_FEATURE_BOARDS_TEXTURES "see boards/*/board.h"
#endif
#ifndef HZ_FEATURE_BOARDS_MIRRORS
#define HZ_FEATURE_BOARDS_MIRRORS "see boards/*/board.h"
#endif
#ifndef HZ_FEATURE_BOARDS_TRANSPARENCY
#define HZ_FEATURE_BOARDS_TRANSPARENCY "see boards/*/board.h"
#endif
#ifndef HZ_FEATURE_BOARDS_MOTION
#define HZ_FEATURE_BOARDS_MOTION "see boards/*/board.h"
#endif

typedef struct feature {
    bool have;
    const char *name, *macro, *boards;
} feature_t;

static const feature_t textures = { HZ_FEATURE_TEXTURES, "textures", "HZ_FEATURE_TEXTURES",
                                    HZ_FEATURE_BOARDS_TEXTURES };
static const feature_t mirrors = { HZ_FEATURE_MIRRORS, "mirrors", "HZ_FEATURE_MIRRORS", HZ_FEATURE_BOARDS_MIRRORS };
static const feature_t transparency = { HZ_FEATURE_TRANSPARENCY, "transparency", "HZ_FEATURE_TRANSPARENCY",
                                        HZ_FEATURE_BOARDS_TRANSPARENCY };
static const feature_t motion = { HZ_FEATURE_MOTION, "motion", "HZ_FEATURE_MOTION", HZ_FEATURE_BOARDS_MOTION };

/* "<what> needs <feature>[ (<why>)], which this build leaves out (<switch> 0; boards with it: ...)[; it also
 * needs <others>]" */
static hz_status_t refuse(hz_error_t *err, const char *what, const feature_t *f, const char *why, const char *also)
{
    return hz_error_set(err, HZ_E_UNSUPPORTED,
                        "%s needs %s%s%s%s, which this build leaves out (%s 0; boards with it: %s)%s%s", what, f->name,
                        *why ? " (" : "", why, *why ? ")" : "", f->macro, f->boards, *also ? "; it also needs " : "",
                        also);
}

hz_status_t hz_render_features_check(const hz_scene_t *s, const hz_render_opts_t *o, hz_error_t *err)
{
    /* the options first: they name one feature each */
    if (!motion.have && o->shutter > 0.0f)
        return refuse(err, "motion blur (shutter > 0)", &motion, "", "");
    if (!transparency.have && o->transparency != HZ_TRANSP_EXACT)
        return refuse(err, "a stochastic transparency method", &transparency, "", "");
    /* the scene: what it has that would render differently without the feature */
    const struct {
        bool need;
        const char *why;
        const feature_t *f;
    } need[] = {
        { (s->features & HZ_FEAT_BLEND) != 0, "blended surfaces", &transparency },
        { (s->features & HZ_FEAT_CUTOUT) != 0, "alpha cutouts", &transparency },
        { (s->features & HZ_FEAT_TEXTURES) && s->uv, "textured materials", &textures },
        { (s->features & HZ_FEAT_MIRROR) && o->max_bounces > 0, "mirror surfaces, bounces > 0",
          &mirrors },
        { (s->features & HZ_FEAT_MOTION) && s->prev_pos, "moving objects", &motion },
    };
    const size_t n = sizeof need / sizeof need[0];
    const feature_t *named[sizeof need / sizeof need[0]];
    size_t first = n, nn = 0, len = 0;
    char also[64] = "";
    for (size_t i = 0; i < n; i++) {
        bool seen = false;
        for (size_t k = 0; k < nn; k++)
            seen = seen || named[k] == need[i].f;
        if (!need[i].need || need[i].f->have || seen)
            continue;
        named[nn++] = need[i].f;
        if (first == n) {
            first = i;
            continue;
        }
        for (const char *c = len ? ", " : ""; *c && len + 1 < sizeof also; c++)
            also[len++] = *c;
        for (const char *c = need[i].f->name; *c && len + 1 < sizeof also; c++)
            also[len++] = *c;
        also[len] = 0;
    }
    return first < n ? refuse(err, "the scene", need[first].f, need[first].why, also) : HZ_OK;
}
