#include "clock.h"
#include "opttab.h"
