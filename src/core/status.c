/* Status codes and their messages, generated from SINTER_STATUS_LIST. */
#include "sinter.h"

const char *sinter_status_string(int status)
{
    switch (status) {
#define SINTER_STATUS_MESSAGE_CASE_(name, value, message)                                   \
    case value:                                                                            \
        return message;
        SINTER_STATUS_LIST(SINTER_STATUS_MESSAGE_CASE_)
#undef SINTER_STATUS_MESSAGE_CASE_
    default:
        return "unknown status";
    }
}

const char *sinter_status_name(int status)
{
    switch (status) {
#define SINTER_STATUS_NAME_CASE_(name, value, message)                                      \
    case value:                                                                            \
        return #name;
        SINTER_STATUS_LIST(SINTER_STATUS_NAME_CASE_)
#undef SINTER_STATUS_NAME_CASE_
    default:
        return "SINTER_STATUS_UNKNOWN";
    }
}

unsigned sinter_version_number(void)
{
    return SINTER_VERSION_NUMBER;
}

const char *sinter_version_string(void)
{
    return SINTER_VERSION_STRING;
}
