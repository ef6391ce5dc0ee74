/* Linked into the Linux package's libexpat.so.1 (scripts/package): Debian 12's expat fills its hash
 * salt with arc4random_buf, which glibc has only since 2.36; this one, hidden inside the library, reads
 * the same kernel entropy through getrandom (glibc 2.25), so the package runs on glibc 2.35 (Ubuntu
 * 22.04) too.  Falls back to /dev/urandom where getrandom is refused (old kernels, seccomp). */
#define _GNU_SOURCE
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/random.h>

__attribute__((visibility("hidden"))) void arc4random_buf(void *buf, size_t n);

void arc4random_buf(void *buf, size_t n)
{
    unsigned char *p = buf;
    while (n > 0) {
        ssize_t got = getrandom(p, n, 0);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            break;
        p += got;
        n -= (size_t)got;
    }
    if (n == 0)
        return;
    FILE *f = fopen("/dev/urandom", "rb");
    if (!f || fread(p, 1, n, f) != n)
        abort(); /* as glibc's arc4random_buf: no entropy is no salt */
    fclose(f);
}
