/* TEMPORARY until the generated Mie tables land: no components. */
#include "aerosol/aerosol_optics.h"

#include <stddef.h>

const aerosol_optics aerosol_optics_table[1];
const int aerosol_optics_count = 0;

const aerosol_optics *aerosol_optics_find(const char *component, int humidity_percent)
{
    return NULL;
}

double aerosol_optics_angle_rad(int j)
{
    double t = (double)j / (AEROSOL_ANGLE_COUNT - 1);
    return 3.14159265358979323846 * t * t;
}
