/* Where the shared presets (biomes, skies, ocio/config.ocio) live. */
#ifndef FM_PRESETS_H
#define FM_PRESETS_H

#include "firmament/firmament.h"

#include <stddef.h>

/* Writes into out the first of: given (when not NULL or empty), $FIRMAMENT_PRESETS, a presets/ holding
 * biomes/ beside the executable (EXE_DIR/presets, EXE_DIR/../presets, EXE_DIR/../share/firmament/
 * presets), the source tree's presets/ (a development build).  None: FM_ERR_INVALID_ARGUMENT with one
 * line naming where it looked (docs/packaging.md). */
fm_status presets_locate(const char *given, char *out, size_t size, fm_error *err);

/* "background, desert-dust, ..." : the names of the .json files in dir, sorted and comma-separated,
 * for messages that list what is known ("no <what> files found in <dir>" when there are none).
 * Returns how many were found. */
int presets_list(const char *dir, const char *what, char *out, size_t size);

/* The file a name or path stands for: a path (holding '/' or ending in .json) as given, else
 * DIR/SUB/NAME.json in the presets folder (presets_locate(presets_dir)), which must exist.  field
 * names the parameter in errors ("biome", "clouds"), what the kind of file ("biome", "cloud").
 * Unknown names fail with one line listing the known ones (after known_first, e.g. "none, "). */
fm_status presets_find(const char *name_or_path, const char *presets_dir, const char *sub, const char *field,
                       const char *what, const char *known_first, char *path, size_t size, fm_error *err);

#endif
