#define _POSIX_C_SOURCE 200809L /* readlink */
#include "base/executable.h"

#include <string.h>

#if defined(_WIN32)
#include <windows.h>

int executable_dir(char *out, size_t size)
{
    wchar_t wide[32768];
    DWORD n = GetModuleFileNameW(NULL, wide, (DWORD)(sizeof wide / sizeof wide[0]));
    out[0] = '\0';
    if (n == 0 || n >= sizeof wide / sizeof wide[0] || size > 0x7fffffff)
        return -1;
    int len = WideCharToMultiByte(CP_UTF8, 0, wide, (int)n, out, (int)size - 1, NULL, NULL);
    if (len <= 0) {
        out[0] = '\0';
        return -1;
    }
    out[len] = '\0';
    char *slash = strrchr(out, '\\');
    if (!slash) {
        out[0] = '\0';
        return -1;
    }
    *slash = '\0';
    return 0;
}

#elif defined(__linux__)
#include <unistd.h>

int executable_dir(char *out, size_t size)
{
    out[0] = '\0';
    if (size < 2)
        return -1;
    ssize_t n = readlink("/proc/self/exe", out, size - 1); /* no terminating NUL from readlink */
    if (n <= 0 || (size_t)n >= size - 1) {
        out[0] = '\0';
        return -1;
    }
    out[n] = '\0';
    char *slash = strrchr(out, '/');
    if (!slash || slash == out) {
        out[0] = '\0';
        return -1;
    }
    *slash = '\0';
    return 0;
}

#else /* macOS and others: untested; _NSGetExecutablePath would go here */

int executable_dir(char *out, size_t size)
{
    if (size)
        out[0] = '\0';
    return -1;
}

#endif
