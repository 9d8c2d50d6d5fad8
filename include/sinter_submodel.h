/*
 * libsinter: the API for people who write submodels (force, heat, electric,
 * neck). Include after sinter.h.
 *
 * Callback conventions (after SUNDIALS):
 *  - every callback table starts with `size_t struct_size` and is copied at
 *    registration; the library reads only the fields the caller's size covers;
 *  - `void *user` is the last argument of every callback;
 *  - a callback returns 0 on success, > 0 for a recoverable failure (the
 *    stepper may retry with a smaller step) and < 0 for a fatal one (the
 *    stepper stops with SINTER_ERR_CALLBACK and keeps the last accepted state);
 *  - an optional destroy_user is called exactly once, when the submodel is
 *    destroyed.
 *
 * Commit/rollback contract: evaluation is pure. A submodel reads the state
 * and its committed per-contact history and writes forces (or heat) and a
 * trial history; the stepper commits the trial history only when a step is
 * accepted. A rejected step leaves the committed history untouched.
 */
#ifndef SINTER_SUBMODEL_H
#define SINTER_SUBMODEL_H

#include "sinter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Callback result values. */
typedef enum sinter_callback_result {
    SINTER_CALLBACK_OK = 0,
    SINTER_CALLBACK_RETRY = 1,
    SINTER_CALLBACK_FATAL = -1
} sinter_callback_result;

#ifdef __cplusplus
}
#endif

#endif /* SINTER_SUBMODEL_H */
