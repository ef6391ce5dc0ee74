/* The JSON sidecar next to each map: what a renderer needs to light a scene with it (sun direction,
 * direct sunlight as a Sun lamp's strength and colour in the map's own units, illuminances) and every
 * parameter that made it.  Groups: "image", "sun", "sky", "parameters" (docs/output.md, "The sidecar"). */
#ifndef FM_IMAGE_SIDECAR_H
#define FM_IMAGE_SIDECAR_H

#include "image/metadata.h"

/* job: a JSON object's text added as "job", or NULL */
fm_status sidecar_write(const char *path, const metadata *meta, const char *job, fm_error *err);

#endif
