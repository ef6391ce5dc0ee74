#include "aerosol/aerosol_optics.h"

#include <string.h>

const aerosol_optics *aerosol_optics_find(const char *component, int humidity_percent)
{
    if (!component)
        return NULL;
    for (int i = 0; i < aerosol_optics_count; i++)
        if (aerosol_optics_table[i].humidity_percent == humidity_percent &&
            strcmp(aerosol_optics_table[i].component, component) == 0)
            return &aerosol_optics_table[i];
    return NULL;
}
