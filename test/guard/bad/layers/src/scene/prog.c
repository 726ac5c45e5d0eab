#include "hz/scene.h"
#include "../../programs/opt/opttab.h"
