#include "../../src/render/render_internal.h"
