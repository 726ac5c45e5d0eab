/* the renderer reaching into a mode: the cycle the guard refuses */
#include "../recon/taa_state.h"
