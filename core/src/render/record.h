/* The render record (fm_render_record): what the map's sidecar and EXR header will report of the
 * sky and the render parameters, gathered once when the map is made. */
#ifndef FM_RENDER_RECORD_H
#define FM_RENDER_RECORD_H

#include "firmament/firmament.h"

void render_record_fill(fm_render_record *r, const fm_sky *sky, const fm_render_params *params);

#endif
