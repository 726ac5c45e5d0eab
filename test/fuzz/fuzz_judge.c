/*
 * String searches for fuzz_import.c's reading of a dead child's report. Compiled without instrumentation and
 * without libc's str* functions: libFuzzer learns the strings a fuzz target compares against (its hooks on
 * strstr, strcmp and the like, and its comparison tracing) and plants them in inputs, and an input that
 * reaches the child's log (a material name in a warning) could then look like a report ("runtime error:", a
 * stack frame of a library) and be misjudged.
 */
#include <stddef.h>

char *hz_fuzz_find(const char *hay, const char *needle);
int hz_fuzz_starts(const char *s, const char *prefix);
int hz_fuzz_ub_report(const char *log);

int hz_fuzz_starts(const char *s, const char *prefix)
{
    while (*prefix)
        if (*s++ != *prefix++)
            return 0;
    return 1;
}

char *hz_fuzz_find(const char *hay, const char *needle)
{
    for (; *hay; hay++)
        if (hz_fuzz_starts(hay, needle))
            return (char *)hay;
    return *needle ? NULL : (char *)hay;
}

/* A UBSan report: a line that starts with a source file of the tree (the compiler's relative path) and goes on
 * with ": runtime error: ". A baker warning that quotes an input starts with "hzbake:". */
int hz_fuzz_ub_report(const char *log)
{
    static const char *const roots[] = { "src/", "programs/", "port/linux/", "test/fuzz/", "include/" };
    for (const char *line = log; line && *line;) {
        for (size_t i = 0; i < sizeof roots / sizeof roots[0]; i++)
            if (hz_fuzz_starts(line, roots[i])) {
                const char *e = line;
                while (*e && *e != '\n' && !hz_fuzz_starts(e, ": runtime error: "))
                    e++;
                if (*e == ':')
                    return 1;
            }
        while (*line && *line != '\n')
            line++;
        line = *line ? line + 1 : NULL;
    }
    return 0;
}
