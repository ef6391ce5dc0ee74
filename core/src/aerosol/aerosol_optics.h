/* Optical properties of the OPAC aerosol components per particle, by wavelength and humidity:
 * Mie theory over each component's log-normal size distribution (tools/aerosol_tables.c). */
#ifndef FM_AEROSOL_AEROSOL_OPTICS_H
#define FM_AEROSOL_AEROSOL_OPTICS_H

#define AEROSOL_WAVELENGTH_COUNT 36 /* 300, 320, ..., 1000 nm */
#define AEROSOL_FIRST_NM 300.0
#define AEROSOL_STEP_NM 20.0
#define AEROSOL_ANGLE_COUNT 301     /* theta_j = pi * (j / (A - 1))^2 */

typedef struct aerosol_optics {
    const char *component; /* OPAC code, e.g. "waso" */
    int humidity_percent;  /* 0, 50, 70, 80, 90, 95, 98, 99 */
    double ext_m2[AEROSOL_WAVELENGTH_COUNT]; /* extinction cross section per particle */
    double sca_m2[AEROSOL_WAVELENGTH_COUNT]; /* scattering cross section per particle */
    double g[AEROSOL_WAVELENGTH_COUNT];      /* asymmetry parameter */
    float phase[AEROSOL_WAVELENGTH_COUNT][AEROSOL_ANGLE_COUNT]; /* sr^-1, integrates to 1 */
} aerosol_optics;

extern const aerosol_optics aerosol_optics_table[];
extern const int aerosol_optics_count;

/* The entry for a component at exactly that humidity, or NULL. */
const aerosol_optics *aerosol_optics_find(const char *component, int humidity_percent);
double aerosol_optics_angle_rad(int j);

#endif
