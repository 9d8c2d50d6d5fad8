/* Names safe as one path component and as XML text. */
#include <string.h>

#include "io/file_name.h"

/* Length of the UTF-8 sequence at s (1 to 4), or 0 when it is not valid UTF-8. */
static int utf8_sequence(const unsigned char *s)
{
    if (s[0] < 0x80)
        return 1;
    int n;
    unsigned lo = 0x80, hi = 0xBF; /* the second byte's range */
    if (s[0] >= 0xC2 && s[0] <= 0xDF)
        n = 2;
    else if (s[0] >= 0xE0 && s[0] <= 0xEF) {
        n = 3;
        if (s[0] == 0xE0)
            lo = 0xA0; /* overlong */
        else if (s[0] == 0xED)
            hi = 0x9F; /* surrogates */
    } else if (s[0] >= 0xF0 && s[0] <= 0xF4) {
        n = 4;
        if (s[0] == 0xF0)
            lo = 0x90; /* overlong */
        else if (s[0] == 0xF4)
            hi = 0x8F; /* past U+10FFFF */
    } else
        return 0;
    if (s[1] < lo || s[1] > hi)
        return 0;
    for (int k = 2; k < n; ++k)
        if ((s[k] & 0xC0) != 0x80)
            return 0;
    return n;
}

int sinter_utf8_valid(const char *text)
{
    const unsigned char *s = (const unsigned char *)text;
    while (*s) {
        const int n = utf8_sequence(s);
        if (n == 0)
            return 0;
        s += n;
    }
    return 1;
}

const char *sinter_file_name_problem(const char *name)
{
    if (*name == '\0')
        return "it is empty";
    if (strchr(name, '/') != NULL || strchr(name, '\\') != NULL)
        return "it holds a path separator ('/' or '\\')";
    if (strstr(name, "..") != NULL)
        return "it holds '..'";
    for (const unsigned char *c = (const unsigned char *)name; *c; ++c)
        if (*c < 0x20 || *c == 0x7f)
            return "it holds a control character";
    if (!sinter_utf8_valid(name))
        return "it is not valid UTF-8";
    return NULL;
}
