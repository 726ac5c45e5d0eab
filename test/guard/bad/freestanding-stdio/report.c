/* Known-bad snippet for the guard tests: stdio in the core. check-freestanding must fail on the include, the
 * printf call and the FILE type, even before looking at symbols. */
#include <stdio.h>
int bad_report(FILE *f, int v)
{
    return printf("%d\n", v) + (f != NULL);
}
