/*
 * deflight.h — the light a scene gets when it brings none.
 *
 * A model baked without a sidecar has an automatic camera but no light, and at the ambient level alone it renders
 * nearly black. The renderer then lights it with one key light placed from the scene itself: at the camera of
 * time 0 (the automatic one frames the bounds from the front), raised by 0.3 and moved left by 0.2 of the
 * camera's distance to its target, so the view sees lit faces with some modelling; no falloff (the scene's scale
 * does not matter) and white of intensity 0.8 π, so a surface facing it shows 0.8 of its albedo.
 *
 * Contract: hz_deflight_place() fills *out for any loaded scene (finite bounds, any camera path); the result is
 * a valid light (finite position, colour >= 0). The renderer (hz_render_create) uses it only when the scene's
 * light_count is 0 and reports it through hz_render_default_light().
 */
#ifndef HZ_DEFLIGHT_H
#define HZ_DEFLIGHT_H

#include "hz/scene.h"

void hz_deflight_place(const hz_scene_t *scene, hz_light_t *out);

#endif
