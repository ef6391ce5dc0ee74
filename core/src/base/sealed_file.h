/* Files of computed tables kept between runs (the live sky's, the clouds' optics): a header (magic,
 * format version, byte order mark, the 32-character key of what the tables were computed from, the
 * payload's size and checksum) and the payload.  Written to a unique temporary name beside the path
 * and renamed over it, so a reader sees a whole old file or a whole new one and concurrent writers
 * leave one whole file; read whole and refused, with the reason, unless every header field matches. */
#ifndef FM_BASE_SEALED_FILE_H
#define FM_BASE_SEALED_FILE_H

#include "firmament/firmament.h"

#include <stddef.h>
#include <stdint.h>

typedef struct sealed_format {
    char magic[8];          /* names the kind of file */
    uint32_t version;       /* of the payload's layout */
    uint64_t checksum_seed; /* hash_bytes' seed for the payload */
    const char *what;       /* "live sky", for the messages */
    const char *other_key;  /* why a file of another key is refused: "the tables of another atmosphere" */
} sealed_format;

fm_status sealed_file_write(const char *path, const sealed_format *format, const char key[32], const void *payload,
                            size_t bytes, fm_error *err);

/* The payload (malloc'd) and its size.  FM_ERR_IO when the file cannot be read,
 * FM_ERR_INVALID_ARGUMENT when it is refused ("live sky 'PATH': corrupt (checksum)"). */
fm_status sealed_file_read(const char *path, const sealed_format *format, const char key[32], unsigned char **payload,
                           size_t *bytes, fm_error *err);

/* Creates the folder dir and those above it that are missing: 0, or -1 with errno set. */
int sealed_file_make_dirs(const char *dir);

#endif
