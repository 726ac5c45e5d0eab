/* Known-bad snippet for the guard tests: calls malloc through a pasted name, so the source scan cannot see
 * it; check-freestanding must still fail because the object references the symbol. */
#include <stddef.h>
#define HIDDEN_CALL(a, b) a##b
void *HIDDEN_CALL(mal, loc)(size_t n);
void *bad_alloc(size_t n)
{
    return HIDDEN_CALL(mal, loc)(n);
}
