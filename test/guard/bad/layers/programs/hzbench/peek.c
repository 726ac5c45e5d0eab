#include "shade_internal.h"
