/*
 * Names that become part of file names and XML text (a scene's `name` names its .pvd file and
 * titles its plot): one path component, valid UTF-8, no control characters.
 */
#ifndef SINTER_IO_FILE_NAME_H
#define SINTER_IO_FILE_NAME_H

/* NULL when `name` is such a name, else what is wrong with it (a static string). */
const char *sinter_file_name_problem(const char *name);

/* 1 when text is valid UTF-8 (no overlong forms, surrogates or code points past U+10FFFF). */
int sinter_utf8_valid(const char *text);

#endif
