/* Known-bad snippet for the guard tests: the float type is pasted together so the token scan misses it;
 * -mgeneral-regs-only must still reject the code on both ISAs. */
#define PASTE(a, b) a##b
int bad_pattern(int x)
{
    PASTE(dou, ble) d = x;
    return (int)(d * 1.5);
}
