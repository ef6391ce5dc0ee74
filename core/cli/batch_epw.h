/* EnergyPlus weather files (EPW): the place of the LOCATION line and, per hour, what a sky map can
 * use.  Format: EnergyPlus "Auxiliary Programs", section "Weather Converter Program", "Data Field
 * Descriptions" (8 header lines, then one line of 35 comma-separated fields per hour). */
#ifndef FM_CLI_BATCH_EPW_H
#define FM_CLI_BATCH_EPW_H

#include <stddef.h>

typedef struct epw_hour {
    int year, month, day;
    int minute_of_day;    /* the middle of the hour the record covers, local standard time */
    double aod550;        /* -1: missing */
    double albedo;        /* -1: missing */
    int sky_cover_tenths; /* -1: missing */
} epw_hour;

typedef struct epw_file {
    char city[64];
    double latitude_deg, longitude_deg, elevation_m;
    int utc_offset_min;
    int count;
    epw_hour *hours;
} epw_file;

/* Returns 0, or 2 with one line in msg naming the line and the field. */
int epw_read(const char *path, epw_file *out, char *msg, size_t msg_size);
void epw_free(epw_file *e);

#endif
