/* base/platform.h on Windows: names arrive in UTF-8 and cross to the system as UTF-16 (the "W"
 * functions), so that any file name works whatever the ANSI code page. */
#define PSAPI_VERSION 2 /* GetProcessMemoryInfo from kernel32 (K32GetProcessMemoryInfo) */
#include "base/platform.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <wchar.h>
#include <windows.h>
#include <psapi.h>
#include <shellapi.h>

/* UTF-8 -> UTF-16 (malloc'd), NULL when not valid UTF-8 or out of memory (errno set). */
static wchar_t *widen(const char *s)
{
    int n = MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, s, -1, NULL, 0);
    wchar_t *w = n > 0 ? malloc((size_t)n * sizeof *w) : NULL;
    if (!w || MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, s, -1, w, n) != n) {
        free(w);
        errno = n > 0 ? ENOMEM : EINVAL;
        return NULL;
    }
    return w;
}

/* UTF-16 -> UTF-8 (malloc'd), or NULL. */
static char *narrow(const wchar_t *w)
{
    int n = WideCharToMultiByte(CP_UTF8, 0, w, -1, NULL, 0, NULL, NULL);
    char *s = n > 0 ? malloc((size_t)n) : NULL;
    if (s && WideCharToMultiByte(CP_UTF8, 0, w, -1, s, n, NULL, NULL) != n) {
        free(s);
        s = NULL;
    }
    return s;
}

/* errno for the calling thread's last Windows error, so that callers print strerror(errno). */
static int fail_with_last_error(void)
{
    switch (GetLastError()) {
    case ERROR_FILE_NOT_FOUND:
    case ERROR_PATH_NOT_FOUND:
    case ERROR_INVALID_DRIVE:
        errno = ENOENT;
        break;
    case ERROR_ACCESS_DENIED:
    case ERROR_SHARING_VIOLATION:
    case ERROR_LOCK_VIOLATION:
        errno = EACCES;
        break;
    case ERROR_FILE_EXISTS:
    case ERROR_ALREADY_EXISTS:
        errno = EEXIST;
        break;
    case ERROR_DISK_FULL:
    case ERROR_HANDLE_DISK_FULL:
        errno = ENOSPC;
        break;
    case ERROR_FILENAME_EXCED_RANGE:
        errno = ENAMETOOLONG;
        break;
    case ERROR_INVALID_NAME:
        errno = EINVAL;
        break;
    default:
        errno = EIO;
    }
    return -1;
}

FILE *platform_fopen(const char *path, const char *mode)
{
    wchar_t wmode[8];
    size_t n = 0;
    for (; mode[n] && n < 6; n++)
        wmode[n] = (wchar_t)mode[n];
    if (!strchr(mode, 'b'))
        wmode[n++] = L'b';
    wmode[n] = 0;
    wchar_t *w = widen(path);
    FILE *f = w ? _wfopen(w, wmode) : NULL;
    free(w);
    return f;
}

int platform_remove(const char *path)
{
    wchar_t *w = widen(path);
    int r = !w ? -1 : DeleteFileW(w) ? 0 : fail_with_last_error();
    free(w);
    return r;
}

int platform_make_dir(const char *path)
{
    wchar_t *w = widen(path);
    int r = !w ? -1 : CreateDirectoryW(w, NULL) ? 0 : GetLastError() == ERROR_ALREADY_EXISTS &&
                                                          platform_path_kind(path) == PLATFORM_DIRECTORY
                                                      ? 0
                                                      : fail_with_last_error();
    free(w);
    return r;
}

/* MoveFileExW replaces an existing destination (rename() on Windows refuses to); it fails, and the
 * destination stays as it was, when another process holds that file open without sharing delete. */
int platform_rename_replace(const char *from, const char *to)
{
    wchar_t *wf = widen(from), *wt = widen(to);
    int r = !wf || !wt ? -1
            : MoveFileExW(wf, wt, MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH) ? 0
                                                                                      : fail_with_last_error();
    free(wf);
    free(wt);
    return r;
}

int platform_link(const char *existing, const char *new_name)
{
    wchar_t *we = widen(existing), *wn = widen(new_name);
    int r = !we || !wn ? -1 : CreateHardLinkW(wn, we, NULL) ? 0 : fail_with_last_error();
    free(we);
    free(wn);
    return r;
}

platform_kind platform_path_kind(const char *path)
{
    wchar_t *w = widen(path);
    DWORD a = w ? GetFileAttributesW(w) : INVALID_FILE_ATTRIBUTES;
    free(w);
    if (a == INVALID_FILE_ATTRIBUTES)
        return PLATFORM_MISSING;
    return a & FILE_ATTRIBUTE_DIRECTORY ? PLATFORM_DIRECTORY : a & FILE_ATTRIBUTE_DEVICE ? PLATFORM_OTHER : PLATFORM_FILE;
}

/* The volume and file index identify a file whatever the spelling of its path. */
static int file_id(const char *path, BY_HANDLE_FILE_INFORMATION *info)
{
    wchar_t *w = widen(path);
    HANDLE h = w ? CreateFileW(w, 0, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE, NULL, OPEN_EXISTING,
                               FILE_FLAG_BACKUP_SEMANTICS, NULL)
                 : INVALID_HANDLE_VALUE;
    free(w);
    if (h == INVALID_HANDLE_VALUE)
        return -1;
    int ok = GetFileInformationByHandle(h, info);
    CloseHandle(h);
    return ok ? 0 : -1;
}

char *platform_link_target(const char *path)
{
    (void)path; /* links need privileges on Windows and are rare: an output link is replaced */
    return NULL;
}

double platform_file_age_s(const char *path)
{
    wchar_t *w = widen(path);
    WIN32_FILE_ATTRIBUTE_DATA data;
    int ok = w && GetFileAttributesExW(w, GetFileExInfoStandard, &data);
    free(w);
    if (!ok)
        return -1.0;
    FILETIME now;
    GetSystemTimeAsFileTime(&now);
    ULARGE_INTEGER a = {.LowPart = data.ftLastWriteTime.dwLowDateTime, .HighPart = data.ftLastWriteTime.dwHighDateTime};
    ULARGE_INTEGER b = {.LowPart = now.dwLowDateTime, .HighPart = now.dwHighDateTime};
    return ((double)b.QuadPart - (double)a.QuadPart) * 1e-7; /* 100 ns units */
}

int platform_same_file(const char *a, const char *b)
{
    BY_HANDLE_FILE_INFORMATION ia, ib;
    if (file_id(a, &ia) != 0 || file_id(b, &ib) != 0)
        return -1;
    return ia.dwVolumeSerialNumber == ib.dwVolumeSerialNumber && ia.nFileIndexHigh == ib.nFileIndexHigh &&
           ia.nFileIndexLow == ib.nFileIndexLow;
}

char *platform_resolve_dir(const char *dir)
{
    if (platform_path_kind(dir) != PLATFORM_DIRECTORY)
        return NULL;
    wchar_t *w = widen(dir);
    DWORD n = w ? GetFullPathNameW(w, 0, NULL, NULL) : 0;
    wchar_t *full = n ? malloc(n * sizeof *full) : NULL;
    char *out = full && GetFullPathNameW(w, n, full, NULL) < n ? narrow(full) : NULL;
    free(full);
    free(w);
    return out;
}

const char *platform_last_separator(const char *path)
{
    const char *slash = strrchr(path, '/'), *backslash = strrchr(path, '\\');
    return slash > backslash ? slash : backslash;
}

int platform_list_dir(const char *dir, void (*fn)(void *ctx, const char *name), void *ctx)
{
    size_t n = strlen(dir);
    char *pattern = malloc(n + 3);
    if (!pattern)
        return -1;
    snprintf(pattern, n + 3, "%s\\*", dir);
    wchar_t *w = widen(pattern);
    free(pattern);
    WIN32_FIND_DATAW found;
    HANDLE h = w ? FindFirstFileW(w, &found) : INVALID_HANDLE_VALUE;
    free(w);
    if (h == INVALID_HANDLE_VALUE)
        return fail_with_last_error();
    do {
        char *name = narrow(found.cFileName);
        if (name && strcmp(name, ".") != 0 && strcmp(name, "..") != 0)
            fn(ctx, name);
        free(name);
    } while (FindNextFileW(h, &found));
    FindClose(h);
    return 0;
}

/* As mkstemp: CREATE_NEW fails on an existing name, so a name is never taken twice. */
struct platform_lock {
    HANDLE file;
};

platform_lock *platform_lock_file(const char *path)
{
    wchar_t *w = widen(path);
    if (!w)
        return NULL;
    /* every holder opens it delete-on-close, so it goes with the last handle; while it is being
     * deleted it cannot be opened, for a moment */
    HANDLE h = INVALID_HANDLE_VALUE;
    for (int attempt = 0; attempt < 1000; attempt++) {
        h = CreateFileW(w, GENERIC_READ | GENERIC_WRITE, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE,
                        NULL, OPEN_ALWAYS, FILE_ATTRIBUTE_HIDDEN | FILE_FLAG_DELETE_ON_CLOSE, NULL);
        if (h != INVALID_HANDLE_VALUE || GetLastError() != ERROR_ACCESS_DENIED)
            break;
        Sleep(10);
    }
    free(w);
    if (h == INVALID_HANDLE_VALUE) {
        fail_with_last_error();
        return NULL;
    }
    OVERLAPPED whole = {0};
    platform_lock *l = malloc(sizeof *l);
    if (!l || !LockFileEx(h, LOCKFILE_EXCLUSIVE_LOCK, 0, 1, 0, &whole)) {
        if (l)
            fail_with_last_error();
        CloseHandle(h);
        free(l);
        return NULL;
    }
    l->file = h;
    return l;
}

void platform_unlock(platform_lock *l)
{
    if (!l)
        return;
    OVERLAPPED whole = {0};
    UnlockFileEx(l->file, 0, 1, 0, &whole);
    CloseHandle(l->file);
    free(l);
}

int platform_create_unique(char *name_template)
{
    static const char chars[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    size_t n = strlen(name_template);
    if (n < 6 || strcmp(name_template + n - 6, "XXXXXX") != 0) {
        errno = EINVAL;
        return -1;
    }
    LARGE_INTEGER t;
    QueryPerformanceCounter(&t);
    unsigned long long x = (unsigned long long)t.QuadPart ^ ((unsigned long long)GetCurrentProcessId() << 32);
    for (int attempt = 0; attempt < 100; attempt++) {
        for (int i = 0; i < 6; i++) {
            x = x * 6364136223846793005ULL + 1442695040888963407ULL; /* Knuth's MMIX LCG */
            name_template[n - 6 + i] = chars[(x >> 33) % (sizeof chars - 1)];
        }
        wchar_t *w = widen(name_template);
        if (!w)
            return -1;
        HANDLE h = CreateFileW(w, GENERIC_WRITE, 0, NULL, CREATE_NEW, FILE_ATTRIBUTE_NORMAL, NULL);
        free(w);
        if (h != INVALID_HANDLE_VALUE) {
            CloseHandle(h);
            return 0;
        }
        if (GetLastError() != ERROR_FILE_EXISTS)
            return fail_with_last_error();
    }
    errno = EEXIST;
    return -1;
}

const char *platform_temp_dir(void)
{
    static char dir[MAX_PATH * 3];
    wchar_t w[MAX_PATH + 1];
    DWORD n = GetTempPathW(MAX_PATH + 1, w);
    if (n == 0 || n > MAX_PATH)
        return ".";
    if (n > 1 && w[n - 1] == L'\\')
        w[n - 1] = 0;
    if (WideCharToMultiByte(CP_UTF8, 0, w, -1, dir, (int)sizeof dir, NULL, NULL) <= 0)
        return ".";
    return dir;
}

int platform_cpu_count(void)
{
    DWORD n = GetActiveProcessorCount(ALL_PROCESSOR_GROUPS);
    return n < 1 ? 1 : (int)n;
}

double platform_monotonic_seconds(void)
{
    LARGE_INTEGER t, f;
    QueryPerformanceCounter(&t);
    QueryPerformanceFrequency(&f);
    return (double)t.QuadPart / (double)f.QuadPart;
}

double platform_peak_memory_mib(void)
{
    PROCESS_MEMORY_COUNTERS pmc;
    return GetProcessMemoryInfo(GetCurrentProcess(), &pmc, sizeof pmc) ? pmc.PeakWorkingSetSize / 1048576.0 : 0.0;
}

/* A console, not a pipe or file (_isatty is also true of the NUL device). */
int platform_stderr_is_terminal(void)
{
    DWORD mode;
    return GetConsoleMode(GetStdHandle(STD_ERROR_HANDLE), &mode) != 0;
}

static void (*interrupt_handler)(int sig);

/* Runs on a thread of its own.  For Ctrl-C and Ctrl-Break the process goes on (TRUE) and stops at
 * the library's next look at the flag; closing the console ends the process when this returns, so
 * it waits the few seconds Windows allows for the main thread to remove its temporary files. */
static BOOL WINAPI on_console_event(DWORD type)
{
    if (type != CTRL_C_EVENT && type != CTRL_BREAK_EVENT && type != CTRL_CLOSE_EVENT)
        return FALSE;
    interrupt_handler(SIGINT);
    if (type == CTRL_CLOSE_EVENT)
        Sleep(4000);
    return TRUE;
}

void platform_on_interrupt(void (*handler)(int sig))
{
    interrupt_handler = handler;
    SetConsoleCtrlHandler(on_console_event, TRUE);
}

void platform_utf8_args(int *argc, char ***argv)
{
    SetConsoleOutputCP(CP_UTF8);
    int n = 0;
    wchar_t **wide = CommandLineToArgvW(GetCommandLineW(), &n);
    char **args = wide && n > 0 ? calloc((size_t)n + 1, sizeof *args) : NULL;
    if (!args)
        return; /* keep the ANSI arguments */
    for (int i = 0; i < n; i++)
        if (!(args[i] = narrow(wide[i])))
            return;
    LocalFree(wide);
    *argc = n;
    *argv = args; /* lives as long as the process, as argv does */
}
