/* Property tables in scenes: inline pairs or a CSV file of (temperature, value) rows. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/path.h"
#include "io/scene_tables.h"
#include "io/text_file.h"

int scene_table_key(const char *key)
{
    const size_t n = strlen(key), k = strlen("_table");
    return n > k && strcmp(key + n - k, "_table") == 0;
}

int scene_table_inline(const scene_entry *e)
{
    const char c = e->value[0];
    return isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.';
}

typedef struct csv_rows {
    sinter_ctx *ctx;
    const char *path;
    double *theta, *value;
    size_t count, capacity;
    int header_allowed; /* no row read yet: a line that is not numbers is a header */
} csv_rows;

/* Two finite numbers separated by commas, semicolons or blanks; 0 if not. */
static int two_numbers(const char *p, double out[2])
{
    for (int k = 0; k < 2; ++k) {
        while (*p == ' ' || *p == '\t' || (k > 0 && (*p == ',' || *p == ';')))
            ++p;
        char *end = NULL;
        errno = 0;
        out[k] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(out[k]))
            return 0;
        p = end;
    }
    while (*p == ' ' || *p == '\t' || *p == '\r')
        ++p;
    return *p == '\0';
}

static sinter_status csv_line(void *user, int line, char *text)
{
    csv_rows *r = user;
    char *hash = strchr(text, '#');
    if (hash != NULL)
        *hash = '\0';
    const char *p = text;
    while (*p == ' ' || *p == '\t' || *p == '\r')
        ++p;
    if (*p == '\0')
        return SINTER_OK;
    double v[2];
    if (!two_numbers(p, v)) {
        if (r->header_allowed) {
            r->header_allowed = 0;
            return SINTER_OK;
        }
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: expected a row 'temperature [K], value' of two finite numbers",
                           r->path, line);
    }
    r->header_allowed = 0;
    if (r->count == r->capacity) {
        const size_t cap = r->capacity ? 2 * r->capacity : 16;
        double *a = sinter_realloc_array(r->ctx, r->theta, cap, sizeof(double));
        if (a == NULL)
            return sinter_last_status(r->ctx);
        r->theta = a;
        double *b = sinter_realloc_array(r->ctx, r->value, cap, sizeof(double));
        if (b == NULL)
            return sinter_last_status(r->ctx);
        r->value = b;
        r->capacity = cap;
    }
    r->theta[r->count] = v[0];
    r->value[r->count++] = v[1];
    return SINTER_OK;
}

sinter_status scene_table_read(scene_text *t, scene_section *s, const char *key, const char *path,
                               double **theta, double **value, size_t *n)
{
    *theta = *value = NULL;
    *n = 0;
    const scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    if (path == NULL) { /* inline pairs */
        double *v = NULL;
        size_t count = 0;
        sinter_status st = scene_get_numbers(t, s, key, &v, &count);
        if (st != SINTER_OK)
            return st;
        if (count % 2 != 0 || count < 2) {
            sinter_free(t->ctx, v);
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: %s: expected pairs 'temperature [K] value', got %zu numbers",
                               t->path, e->line, key, count);
        }
        *theta = sinter_calloc(t->ctx, count / 2, sizeof(double));
        *value = sinter_calloc(t->ctx, count / 2, sizeof(double));
        if (*theta == NULL || *value == NULL) {
            sinter_free(t->ctx, v);
            return SINTER_ERR_NOMEM;
        }
        for (size_t k = 0; k < count / 2; ++k) {
            (*theta)[k] = v[2 * k];
            (*value)[k] = v[2 * k + 1];
        }
        *n = count / 2;
        sinter_free(t->ctx, v);
        return SINTER_OK;
    }
    char where[SINTER_PATH_SIZE + 32];
    snprintf(where, sizeof(where), "%s:%d: %s: ", t->path, e->line, key);
    FILE *f = NULL;
    sinter_status st = sinter_text_open(t->ctx, where, "property table", path, &f);
    if (st != SINTER_OK)
        return st;
    csv_rows r = {t->ctx, path, NULL, NULL, 0, 0, 1};
    char buf[512];
    st = sinter_text_each_line(t->ctx, f, path, "a property table", buf, sizeof(buf), csv_line, &r);
    fclose(f);
    if (st == SINTER_OK && r.count == 0)
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s: holds no row 'temperature, value'", path);
    if (st != SINTER_OK) {
        sinter_free(t->ctx, r.theta);
        sinter_free(t->ctx, r.value);
        return st;
    }
    *theta = r.theta;
    *value = r.value;
    *n = r.count;
    return SINTER_OK;
}
