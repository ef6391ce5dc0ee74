/* Where the shared presets (biomes, skies) live: the caller's directory, else $FIRMAMENT_PRESETS,
 * else the source tree's presets/ (a build that was not installed), else the installed copy. */
#ifndef FM_PRESETS_H
#define FM_PRESETS_H

const char *presets_dir(const char *given);

#endif
