/* a mode reaching into the renderer internals */
#include "../render/render_internal.h"
