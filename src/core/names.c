/* Looking up models and their parameters by name. */
#include <string.h>

#include "core.h"

int sinter_find_key(const char *const *keys, int max, const char *key)
{
    for (int k = 0; k < max && keys[k] != NULL; ++k)
        if (strcmp(keys[k], key) == 0)
            return k;
    return -1;
}

sinter_status sinter_unknown_key(sinter_ctx *ctx, const char *what, const char *name,
                                const char *key, const char *const *keys, int max)
{
    char known[256] = "";
    for (int k = 0; k < max && keys[k] != NULL; ++k) {
        const size_t used = strlen(known);
        if (used + strlen(keys[k]) + 3 >= sizeof(known))
            break;
        if (k > 0)
            strcat(known, ", ");
        strcat(known, keys[k]);
    }
    return sinter_fail(ctx, SINTER_ERR_NOT_FOUND, "%s '%s' has no parameter '%s' (%s%s)", what,
                       name, key, known[0] != '\0' ? "known: " : "it has no parameters", known);
}

void sinter_join_names(char *buf, size_t size, size_t count, const char *(*name_at)(size_t k))
{
    if (size == 0)
        return;
    buf[0] = '\0';
    for (size_t k = 0; k < count; ++k) {
        const size_t used = strlen(buf);
        if (used + 3 >= size)
            break;
        strncat(buf, name_at(k), size - used - 3);
        if (k + 1 < count)
            strncat(buf, ", ", size - strlen(buf) - 1);
    }
}
