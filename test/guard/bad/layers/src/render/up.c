#include "hz/render.h"
#include "../../port/linux/cli.h"
