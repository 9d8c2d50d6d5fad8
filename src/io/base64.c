/* Base64 (RFC 4648) encoding to a stream; see base64.h. */
#include "io/base64.h"

static const char ALPHABET[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void flush_text(sinter_base64 *b)
{
    if (b->used > 0)
        fwrite(b->text, 1, b->used, b->fp);
    b->used = 0;
}

/* Three bytes (n of them real, 1-3) as four characters, '=' for the missing ones. */
static void encode3(sinter_base64 *b, const unsigned char *in, int n)
{
    if (b->used + 4 > sizeof(b->text))
        flush_text(b);
    const unsigned long v = ((unsigned long)in[0] << 16) |
                            ((unsigned long)(n > 1 ? in[1] : 0) << 8) | (n > 2 ? in[2] : 0);
    char *out = b->text + b->used;
    out[0] = ALPHABET[(v >> 18) & 63];
    out[1] = ALPHABET[(v >> 12) & 63];
    out[2] = n > 1 ? ALPHABET[(v >> 6) & 63] : '=';
    out[3] = n > 2 ? ALPHABET[v & 63] : '=';
    b->used += 4;
}

void sinter_base64_begin(sinter_base64 *b, FILE *fp)
{
    b->fp = fp;
    b->held_count = 0;
    b->used = 0;
}

void sinter_base64_put(sinter_base64 *b, const unsigned char *bytes, size_t n)
{
    size_t k = 0;
    while (b->held_count > 0 && b->held_count < 3 && k < n)
        b->held[b->held_count++] = bytes[k++];
    if (b->held_count == 3) {
        encode3(b, b->held, 3);
        b->held_count = 0;
    }
    for (; k + 3 <= n; k += 3)
        encode3(b, bytes + k, 3);
    while (k < n)
        b->held[b->held_count++] = bytes[k++];
}

void sinter_base64_end(sinter_base64 *b)
{
    if (b->held_count > 0)
        encode3(b, b->held, b->held_count);
    b->held_count = 0;
    flush_text(b);
}
