/* base/platform.h on POSIX systems (Linux, macOS): file names are bytes, used as given. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "base/platform.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

FILE *platform_fopen(const char *path, const char *mode)
{
    return fopen(path, mode);
}

int platform_remove(const char *path)
{
    return unlink(path);
}

int platform_make_dir(const char *path)
{
    return mkdir(path, 0777) == 0 || (errno == EEXIST && platform_path_kind(path) == PLATFORM_DIRECTORY) ? 0 : -1;
}

int platform_rename_replace(const char *from, const char *to)
{
    return rename(from, to);
}

int platform_link(const char *existing, const char *new_name)
{
    return link(existing, new_name);
}

platform_kind platform_path_kind(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return PLATFORM_MISSING;
    return S_ISREG(st.st_mode) ? PLATFORM_FILE : S_ISDIR(st.st_mode) ? PLATFORM_DIRECTORY : PLATFORM_OTHER;
}

char *platform_link_target(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0 || !S_ISLNK(st.st_mode))
        return NULL;
    return realpath(path, NULL);
}

double platform_file_age_s(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? difftime(time(NULL), st.st_mtime) : -1.0;
}

int platform_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0)
        return -1;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

char *platform_resolve_dir(const char *dir)
{
    return realpath(dir, NULL);
}

const char *platform_last_separator(const char *path)
{
    return strrchr(path, '/');
}

int platform_list_dir(const char *dir, void (*fn)(void *ctx, const char *name), void *ctx)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            fn(ctx, e->d_name);
    closedir(d);
    return 0;
}

struct platform_lock {
    int fd;
    char path[]; /* removed on unlock */
};

/* 1 when fd is the file now named path: the previous holder may have removed it as it let go. */
static int still_named(int fd, const char *path)
{
    struct stat held, named;
    return fstat(fd, &held) == 0 && stat(path, &named) == 0 && held.st_dev == named.st_dev &&
           held.st_ino == named.st_ino;
}

platform_lock *platform_lock_file(const char *path)
{
    platform_lock *l = malloc(sizeof *l + strlen(path) + 1);
    if (!l)
        return NULL;
    strcpy(l->path, path);
    for (;;) {
        l->fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
        if (l->fd < 0)
            break;
        struct flock fl = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
        int r;
        while ((r = fcntl(l->fd, F_SETLKW, &fl)) != 0 && errno == EINTR)
            ;
        if (r == 0 && still_named(l->fd, path))
            return l;
        int e = errno;
        close(l->fd);
        if (r != 0) {
            errno = e;
            break;
        }
    }
    free(l);
    return NULL;
}

void platform_unlock(platform_lock *l)
{
    if (!l)
        return;
    unlink(l->path); /* before the release: a waiter then sees a removed file and opens the next */
    close(l->fd);
    free(l);
}

/* O_EXCL with mode 0666: the kernel applies the umask as to any new file (mkstemp's 0600 would need
 * the umask, which only umask() reads, setting it process-wide for a moment). */
int platform_create_unique(char *name_template)
{
    static const char letters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    size_t len = strlen(name_template);
    if (len < 6 || strcmp(name_template + len - 6, "XXXXXX") != 0) {
        errno = EINVAL;
        return -1;
    }
    for (int attempt = 0; attempt < 100; attempt++) {
        uint64_t r = 0;
        if (getrandom(&r, sizeof r, 0) != (ssize_t)sizeof r) {
            struct timespec t;
            clock_gettime(CLOCK_MONOTONIC, &t);
            r = ((uint64_t)t.tv_nsec << 20) ^ (uint64_t)getpid() ^ (uint64_t)attempt * 0x9E3779B97F4A7C15u;
        }
        for (size_t i = len - 6; i < len; i++, r /= 62)
            name_template[i] = letters[r % 62];
        int fd = open(name_template, O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
        if (fd >= 0)
            return close(fd);
        if (errno != EEXIST)
            return -1;
    }
    return -1;
}

const char *platform_temp_dir(void)
{
    const char *dir = getenv("TMPDIR");
    return dir && dir[0] ? dir : "/tmp";
}

int platform_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 4096 ? 4096 : (int)n;
}

double platform_monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Linux reports ru_maxrss in KiB. */
double platform_peak_memory_mib(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss / 1024.0 : 0.0;
}

int platform_stderr_is_terminal(void)
{
    return isatty(STDERR_FILENO);
}

void platform_on_interrupt(void (*handler)(int sig))
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    sigaction(SIGPIPE, &sa, NULL);
}

void platform_utf8_args(int *argc, char ***argv)
{
}
