#include "stab_util.h"
static void c_stub(stab_result_t *r) { (void)r; }
static const stab_case_t cases[] = { { "stub", "stub", c_stub, 0 } };
STAB_STAGE(timing, cases);
