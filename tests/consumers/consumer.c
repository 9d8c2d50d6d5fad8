/* Builds against the installed libsinter (pkg-config or find_package) and checks the version. */
#include <stdio.h>
#include <string.h>

#include <sinter.h>

int main(void)
{
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    const int same = sinter_version_number() == SINTER_VERSION_NUMBER &&
                     strcmp(sinter_version_string(), SINTER_VERSION_STRING) == 0;
    printf("consumer: header %s, library %s\n", SINTER_VERSION_STRING, sinter_version_string());
    sinter_ctx_destroy(ctx);
    return same ? 0 : 1;
}
