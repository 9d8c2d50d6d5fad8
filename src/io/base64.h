/* Base64 (RFC 4648, with padding) written to a stream as the bytes arrive: the encoding of the
 * VTK XML files' inline binary arrays (src/io/vtu.c). */
#ifndef SINTER_IO_BASE64_H
#define SINTER_IO_BASE64_H

#include <stddef.h>
#include <stdio.h>

typedef struct sinter_base64 {
    FILE *fp;
    unsigned char held[3]; /* bytes not yet encoded (fewer than three) */
    int held_count;
    size_t used; /* characters in text */
    char text[4096];
} sinter_base64;

void sinter_base64_begin(sinter_base64 *b, FILE *fp);
/* Encode n bytes (the stream continues across calls). */
void sinter_base64_put(sinter_base64 *b, const unsigned char *bytes, size_t n);
/* Encode what is held, padded with '=', and write out everything. */
void sinter_base64_end(sinter_base64 *b);

#endif
