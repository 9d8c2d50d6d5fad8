/* Reading scene files into sections and entries, with typed getters. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/text_file.h"
#include "scene_text.h"

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r')
        ++s;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n'))
        s[--n] = '\0';
    return s;
}

void scene_text_free(scene_text *t)
{
    for (size_t k = 0; k < t->count; ++k) {
        scene_section *s = &t->sections[k];
        for (size_t e = 0; e < s->count; ++e) {
            sinter_free(t->ctx, s->entries[e].key);
            sinter_free(t->ctx, s->entries[e].value);
        }
        sinter_free(t->ctx, s->entries);
        sinter_key_set_free(t->ctx, &s->keys);
        sinter_free(t->ctx, s->type);
        sinter_free(t->ctx, s->name);
    }
    sinter_free(t->ctx, t->sections);
    sinter_free(t->ctx, t->path);
    memset(t, 0, sizeof(*t));
}

static int valid_word(const char *w)
{
    if (*w == '\0')
        return 0;
    for (; *w; ++w)
        if (!(*w == '_' || *w == '-' || *w == '.' || (*w >= 'a' && *w <= 'z') ||
              (*w >= 'A' && *w <= 'Z') || (*w >= '0' && *w <= '9')))
            return 0;
    return 1;
}

static sinter_status parse_line(scene_text *t, char *text, int line)
{
    sinter_ctx *ctx = t->ctx;
    char *hash = strchr(text, '#');
    if (hash)
        *hash = '\0';
    char *s = trim(text);
    if (*s == '\0')
        return SINTER_OK;
    if (*s == '[') {
        char *close = strchr(s, ']');
        if (close == NULL || *trim(close + 1) != '\0')
            return sinter_fail(ctx, SINTER_ERR_PARSE,
                               "%s:%d: expected a section header '[type name]', got '%.60s'",
                               t->path, line, s);
        *close = '\0';
        char *inner = trim(s + 1);
        char *space = strpbrk(inner, " \t");
        char *name = (char *)"";
        if (space) {
            *space = '\0';
            name = trim(space + 1);
        }
        if (!valid_word(inner) || (*name && !valid_word(name)))
            return sinter_fail(ctx, SINTER_ERR_PARSE,
                               "%s:%d: expected '[type name]' with words of letters, digits, "
                               "'_', '-' or '.', got '[%.40s %.40s]'",
                               t->path, line, inner, name);
        sinter_status st = sinter_grow(ctx, (void **)&t->sections, &t->capacity, t->count + 1,
                                       sizeof(scene_section));
        if (st != SINTER_OK)
            return st;
        scene_section *sec = &t->sections[t->count];
        memset(sec, 0, sizeof(*sec));
        sec->line = line;
        sec->type = sinter_strdup(ctx, inner);
        sec->name = sinter_strdup(ctx, name);
        t->count++;
        return (sec->type && sec->name) ? SINTER_OK : SINTER_ERR_NOMEM;
    }
    char *eq = strchr(s, '=');
    if (eq == NULL)
        return sinter_fail(ctx, SINTER_ERR_PARSE, "%s:%d: expected 'key = value', got '%.60s'",
                           t->path, line, s);
    *eq = '\0';
    char *key = trim(s), *value = trim(eq + 1);
    if (!valid_word(key))
        return sinter_fail(ctx, SINTER_ERR_PARSE, "%s:%d: expected a key before '=', got '%.40s'",
                           t->path, line, key);
    if (*value == '\0')
        return sinter_fail(ctx, SINTER_ERR_PARSE, "%s:%d: expected a value after '%s ='", t->path,
                           line, key);
    if (t->count == 0)
        return sinter_fail(ctx, SINTER_ERR_PARSE,
                           "%s:%d: expected a section header '[type name]' before '%s = ...'",
                           t->path, line, key);
    scene_section *sec = &t->sections[t->count - 1];
    const size_t first = sinter_key_set_find(&sec->keys, key);
    if (first != SIZE_MAX)
        return sinter_fail(ctx, SINTER_ERR_PARSE,
                           "%s:%d: key '%s' is given twice in [%s%s%s] (first on line %d)", t->path,
                           line, key, sec->type, *sec->name ? " " : "", sec->name,
                           sec->entries[first].line);
    sinter_status st = sinter_grow(ctx, (void **)&sec->entries, &sec->capacity, sec->count + 1,
                                   sizeof(scene_entry));
    if (st != SINTER_OK)
        return st;
    scene_entry *en = &sec->entries[sec->count];
    en->key = sinter_strdup(ctx, key);
    en->value = sinter_strdup(ctx, value);
    en->line = line;
    en->used = 0;
    if (en->key == NULL || en->value == NULL) {
        sinter_free(ctx, en->key);
        sinter_free(ctx, en->value);
        return SINTER_ERR_NOMEM;
    }
    st = sinter_key_set_insert(ctx, &sec->keys, en->key, sec->count);
    if (st != SINTER_OK) {
        sinter_free(ctx, en->key);
        sinter_free(ctx, en->value);
        return st;
    }
    sec->count++;
    return SINTER_OK;
}

sinter_status scene_text_read(scene_text *t, sinter_ctx *ctx, const char *path)
{
    memset(t, 0, sizeof(*t));
    t->ctx = ctx;
    t->path = sinter_strdup(ctx, path);
    if (t->path == NULL)
        return SINTER_ERR_NOMEM;
    FILE *f = NULL;
    sinter_status st = sinter_text_open(ctx, "", "scene file", path, &f);
    if (st != SINTER_OK)
        return st;
    char buf[4096];
    int line = 0;
    while (st == SINTER_OK) {
        const sinter_line_result got = sinter_text_line(f, buf, sizeof(buf));
        if (got == SINTER_LINE_END)
            break;
        ++line;
        if (got == SINTER_LINE_OK)
            st = parse_line(t, buf, line);
        else if (got == SINTER_LINE_TOO_LONG)
            st = sinter_fail(ctx, SINTER_ERR_PARSE, "%s:%d: line longer than %zu characters", path,
                             line, sizeof(buf) - 1);
        else if (got == SINTER_LINE_NUL)
            st =
                sinter_fail(ctx, SINTER_ERR_PARSE,
                            "%s:%d: a NUL byte inside the line (a scene file is text)", path, line);
        else
            st = sinter_fail(ctx, SINTER_ERR_IO, "%s:%d: error reading the scene file: %s", path,
                             line, strerror(errno));
    }
    fclose(f);
    if (st == SINTER_OK && t->count == 0)
        st = sinter_fail(ctx, SINTER_ERR_PARSE, "%s: the file has no sections", path);
    return st;
}

scene_entry *scene_find(scene_section *s, const char *key)
{
    const size_t e = sinter_key_set_find(&s->keys, key);
    if (e == SIZE_MAX)
        return NULL;
    s->entries[e].used = 1;
    return &s->entries[e];
}

static sinter_status expected(scene_text *t, const scene_entry *e, const char *what)
{
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: %s: expected %s, got '%.60s'", t->path,
                       e->line, e->key, what, e->value);
}

/* Parse up to max numbers; returns the count or -1 on a malformed token. */
static long parse_numbers(const char *text, double *out, size_t max)
{
    const char *p = text;
    long n = 0;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == ';')
            ++p;
        if (*p == '\0')
            return n;
        char *end = NULL;
        errno = 0;
        const double v = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v))
            return -1;
        if (*end != '\0' && *end != ' ' && *end != '\t' && *end != ',' && *end != ';')
            return -1;
        if (out != NULL && (size_t)n < max)
            out[n] = v;
        ++n;
        p = end;
    }
}

sinter_status scene_get_double(scene_text *t, scene_section *s, const char *key, double *out)
{
    scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    double v;
    if (parse_numbers(e->value, &v, 1) != 1)
        return expected(t, e, "one finite number (SI units)");
    *out = v;
    return SINTER_OK;
}

sinter_status scene_get_vec3(scene_text *t, scene_section *s, const char *key, double out[3])
{
    scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    double v[3];
    if (parse_numbers(e->value, v, 3) != 3)
        return expected(t, e, "three finite numbers 'x y z' (SI units)");
    memcpy(out, v, sizeof(v));
    return SINTER_OK;
}

sinter_status scene_get_word(scene_text *t, scene_section *s, const char *key, const char **out)
{
    scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    if (strpbrk(e->value, " \t") != NULL)
        return expected(t, e, "a single word");
    *out = e->value;
    return SINTER_OK;
}

sinter_status scene_get_bool(scene_text *t, scene_section *s, const char *key, int *out)
{
    scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    if (strcmp(e->value, "yes") == 0 || strcmp(e->value, "true") == 0 || strcmp(e->value, "1") == 0)
        *out = 1;
    else if (strcmp(e->value, "no") == 0 || strcmp(e->value, "false") == 0 ||
             strcmp(e->value, "0") == 0)
        *out = 0;
    else
        return expected(t, e, "yes or no");
    return SINTER_OK;
}

sinter_status scene_get_numbers(scene_text *t, scene_section *s, const char *key, double **values,
                                size_t *count)
{
    scene_entry *e = scene_find(s, key);
    if (e == NULL)
        return SINTER_ERR_NOT_FOUND;
    const long n = parse_numbers(e->value, NULL, 0);
    if (n <= 0)
        return expected(t, e, "a list of finite numbers");
    double *v = sinter_calloc(t->ctx, (size_t)n, sizeof(double));
    if (v == NULL)
        return SINTER_ERR_NOMEM;
    parse_numbers(e->value, v, (size_t)n);
    *values = v;
    *count = (size_t)n;
    return SINTER_OK;
}

sinter_status scene_check_unused(scene_text *t)
{
    for (size_t k = 0; k < t->count; ++k) {
        scene_section *s = &t->sections[k];
        for (size_t e = 0; e < s->count; ++e)
            if (!s->entries[e].used)
                return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: unknown key '%s' in [%s%s%s]",
                                   t->path, s->entries[e].line, s->entries[e].key, s->type,
                                   *s->name ? " " : "", s->name);
    }
    return SINTER_OK;
}
