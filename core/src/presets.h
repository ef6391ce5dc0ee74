/* Where the shared presets (biomes, skies) live: the caller's directory, else $FIRMAMENT_PRESETS,
 * else the source tree's presets/ (a build that was not installed), else the installed copy. */
#ifndef FM_PRESETS_H
#define FM_PRESETS_H

#include <stddef.h>

const char *presets_dir(const char *given);

/* "background, desert-dust, ..." : the names of the .json files in dir, sorted and comma-separated,
 * for messages that list what is known ("no <what> files found in <dir>" when there are none). */
void presets_list(const char *dir, const char *what, char *out, size_t size);

#endif
