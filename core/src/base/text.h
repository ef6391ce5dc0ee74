/* Small text helpers shared by the library and the executable. */
#ifndef FM_BASE_TEXT_H
#define FM_BASE_TEXT_H

/* A malloc'ed copy of s (free() it), or NULL when memory ran out: C17 has no strdup. */
char *text_copy(const char *s);

#endif
