#include "hz/render.h"
#include "../../src/render/render_internal.h"
