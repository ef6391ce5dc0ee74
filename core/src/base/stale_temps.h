/* Temporaries that a killed process left behind: a file reserved under a unique name beside its
 * final path (platform_create_unique) and never renamed over it.  The next writer of a file of the
 * same kind removes them once they are old enough that no live writer still holds them. */
#ifndef FM_BASE_STALE_TEMPS_H
#define FM_BASE_STALE_TEMPS_H

#include <stddef.h>

/* Removes the regular files in the folder of tmp (a temporary just reserved, its name ending in the
 * six letters or digits that replaced "XXXXXX") that were last modified more than max_age_s seconds
 * ago and whose names are tmp's but for those six characters, any letters or digits, and the
 * characters [any_from, any_to) of the name (a key), any lowercase hexadecimal digits (any_from ==
 * any_to: none). */
void stale_temps_remove(const char *tmp, size_t any_from, size_t any_to, double max_age_s);

#endif
