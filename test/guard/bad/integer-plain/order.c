/* Known-bad snippet for the guard tests: a float in integer-only code. */
int bad_pattern(int x)
{
    float f = (float)x * 0.5f;
    return (int)f;
}
