// Builds against the installed libsinter and its C++ header sinter.hpp (pkg-config or
// find_package): checks the version and that a failing call throws sinter::error with the
// library's message.
#include <cstdio>
#include <cstring>

#include <sinter.hpp>

int main()
{
    const bool same = sinter::version_number() == SINTER_VERSION_NUMBER &&
                      std::strcmp(sinter::version_string(), SINTER_VERSION_STRING) == 0;
    std::printf("C++ consumer: header %s, library %s\n", SINTER_VERSION_STRING,
                sinter::version_string());
    sinter::context ctx;
    sinter::material grain(ctx, "grain");
    try {
        grain.set(sinter::material_param::density, -1.0);
    } catch (const sinter::error &e) {
        std::printf("C++ consumer: caught %s\n", e.what());
        return same && e.code() == sinter::status::invalid && !e.message().empty() ? 0 : 1;
    }
    std::printf("C++ consumer: no exception for a negative density\n");
    return 1;
}
