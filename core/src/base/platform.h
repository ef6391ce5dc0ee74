/* What differs between operating systems, behind one interface: files by UTF-8 name, replacing a
 * file by another, temporary names, the console's interrupt, clocks and the processor count.
 * platform_posix.c (Linux, macOS) and platform_windows.c (Windows: the wide-character API at the
 * boundary, so that names are UTF-8 everywhere else) implement it; CMake builds one of them.
 * Functions returning int give 0 on success, else -1 with errno set. */
#ifndef FM_BASE_PLATFORM_H
#define FM_BASE_PLATFORM_H

#include <stdio.h>

/* fopen by UTF-8 name; always binary, so that a file holds the same bytes on every system. */
FILE *platform_fopen(const char *path, const char *mode);
int platform_remove(const char *path);
/* Creates a directory (its parent must exist); an existing directory is no error. */
int platform_make_dir(const char *path);
/* Renames from over to, replacing an existing to (as one step where the system can). */
int platform_rename_replace(const char *from, const char *to);
/* A second name (hard link) for an existing file. */
int platform_link(const char *existing, const char *new_name);

/* The longest path and file name, in bytes, that the system takes (Windows: MAX_PATH and the
 * 255 UTF-16 units of a name, which a UTF-8 name of 255 bytes never exceeds). */
#ifdef _WIN32
#define PLATFORM_PATH_MAX 260
#else
#include <limits.h>
#define PLATFORM_PATH_MAX PATH_MAX
#endif
#define PLATFORM_NAME_MAX 255

/* When path is a symbolic link to an existing file, that file's path (malloc'd, links resolved);
 * else NULL (Windows: always NULL, links are replaced as files). */
char *platform_link_target(const char *path);
/* Seconds since the file was last modified, or -1 when it cannot be looked at. */
double platform_file_age_s(const char *path);

typedef enum { PLATFORM_MISSING, PLATFORM_FILE, PLATFORM_DIRECTORY, PLATFORM_OTHER } platform_kind;
platform_kind platform_path_kind(const char *path);
/* 1 when a and b are one existing file, 0 when not, -1 when either cannot be looked at. */
int platform_same_file(const char *a, const char *b);
/* The absolute path of an existing directory, links resolved (malloc'd), or NULL. */
char *platform_resolve_dir(const char *dir);
/* The last directory separator of path ('/', and '\\' on Windows), or NULL. */
const char *platform_last_separator(const char *path);
/* Calls fn for each entry of dir (not "." nor ".."); -1 when dir cannot be read. */
int platform_list_dir(const char *dir, void (*fn)(void *ctx, const char *name), void *ctx);

/* Creates a new empty file named template with its trailing "XXXXXX" replaced (as mkstemp), with
 * the permissions of a new file. */
int platform_create_unique(char *name_template);
/* An exclusive lock on the file at path (created if missing), waiting while another process holds
 * it; NULL with errno set on failure.  The system releases it when the process dies (SIGKILL too). */
typedef struct platform_lock platform_lock;
platform_lock *platform_lock_file(const char *path);
/* Removes the lock file and releases the lock (NULL: nothing). */
void platform_unlock(platform_lock *lock);
/* The folder for private temporary files ($TMPDIR, /tmp; Windows: GetTempPath). */
const char *platform_temp_dir(void);

int platform_cpu_count(void);
double platform_monotonic_seconds(void);
double platform_peak_memory_mib(void);
int platform_stderr_is_terminal(void);

/* Calls handler(signal number) on an interrupt: SIGINT, SIGTERM, SIGHUP, SIGPIPE on POSIX (the
 * handler must only set a flag); Ctrl-C, Ctrl-Break and closing the console window on Windows
 * (reported as SIGINT, from a thread the system starts). */
void platform_on_interrupt(void (*handler)(int sig));

/* Windows: replaces argv by the command line's arguments in UTF-8 and makes the console print
 * UTF-8; elsewhere nothing (the arguments are the bytes given). */
void platform_utf8_args(int *argc, char ***argv);

#endif
