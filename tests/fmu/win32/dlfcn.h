/*
 * Test only (tests/fmu/test_platforms.py): the few POSIX calls of examples/c/plate_host.c over
 * the Windows API, so that the unchanged host builds with mingw-w64 and loads the FMU's DLL under
 * Wine. dlopen is LoadLibraryA (with the path's '/' turned into '\'), dlsym GetProcAddress,
 * realpath _fullpath. Nothing of this goes into the FMU.
 */
#ifndef PLATE_IMPACT_TEST_DLFCN_H
#define PLATE_IMPACT_TEST_DLFCN_H

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <windows.h>

#define RTLD_NOW 2
#define RTLD_LOCAL 0

static char dlfcn_message[64];

static inline void *dlopen(const char *path, int mode) {
    (void)mode;
    char windows_path[PATH_MAX];
    snprintf(windows_path, sizeof windows_path, "%s", path);
    for (char *c = windows_path; *c; c++)
        if (*c == '/') *c = '\\';
    HMODULE module = LoadLibraryA(windows_path);
    if (!module)
        snprintf(dlfcn_message, sizeof dlfcn_message, "LoadLibrary failed with error %lu",
                 (unsigned long)GetLastError());
    return (void *)module;
}

static inline void *dlsym(void *library, const char *name) {
    FARPROC function = GetProcAddress((HMODULE)library, name);
    void *pointer;
    memcpy(&pointer, &function, sizeof pointer);
    return pointer;
}

static inline int dlclose(void *library) { return FreeLibrary((HMODULE)library) ? 0 : -1; }

static inline const char *dlerror(void) { return dlfcn_message; }

#define realpath(path, resolved) _fullpath((resolved), (path), PATH_MAX)

#endif
