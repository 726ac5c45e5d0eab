#include "stab.h"
static void c_placeholder(stab_result_t *r) { (void)r; }
static const stab_case_t cases[] = { { "placeholder", "x", c_placeholder, 0 } };
STAB_STAGE(dither, cases);
