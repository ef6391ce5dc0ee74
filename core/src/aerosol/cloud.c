#include "aerosol/cloud.h"
#include "aerosol/ice_halo.h"

#include "base/status.h"
#include "base/units.h"
#include "data/tables.h"
#include "phase/phase_hg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Droplet spectra: the headers of OPAC's optdat files (Hess, Koepke & Schult 1998), dN/dr = A r^alpha
 * exp(-B r^gamma) over 0.02-50 um; effective radii 7.33 um (stco), 11.3 um (stma), 10.7 um (fogr).
 * The genera without an OPAC spectrum of their own take the nearest one: altostratus the continental
 * stratus, nimbostratus the maritime.  The default layers are presets/clouds/TYPE.json. */
#define STCO {5.0, 0.938, 1.05, 0.02, 50.0}
#define STMA {3.0, 0.193, 1.3, 0.02, 50.0}
#define FOGR {4.0, 0.0562, 1.77, 0.02, 50.0}
#define NO_SIZE {0.0, 0.0, 0.0, 0.0, 0.0}

const cloud_type cloud_types[] = {
    {"stratus", 0, STCO, "OPAC stratus (continental)"},
    {"stratocumulus", 0, STMA, "OPAC stratus (maritime)"},
    {"altostratus", 0, STCO, "OPAC stratus (continental)"},
    {"nimbostratus", 0, STMA, "OPAC stratus (maritime)"},
    {"fog", 0, FOGR, "OPAC fog"},
    {"cirrostratus", 1, NO_SIZE, "two-term Henyey-Greenstein, g = 0.77"},
    {"cirrus", 1, NO_SIZE, "two-term Henyey-Greenstein, g = 0.77"},
    {NULL, 0, NO_SIZE, NULL},
};

const cloud_type *cloud_type_find(const char *name)
{
    for (const cloud_type *t = cloud_types; name && t->name; t++)
        if (strcmp(t->name, name) == 0)
            return t;
    return NULL;
}

void cloud_type_names(char *out, size_t size)
{
    size_t used = 0;
    if (size)
        out[0] = '\0';
    for (const cloud_type *t = cloud_types; t->name && used < size; t++) {
        int n = snprintf(out + used, size - used, "%s%s", t == cloud_types ? "" : ", ", t->name);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

double cloud_angle_rad(int j)
{
    double t = (double)j / (CLOUD_ANGLE_COUNT - 1);
    return FM_PI * t * t;
}

/* Ice: p = (1 - h) [f HG(g1) + (1 - f) HG(-g2)] + h halo.  The forward lobe carries the diffraction
 * and the refracted light, the backward one the internal reflections of hexagonal crystals; the
 * halo (aerosol/ice_halo.h) the light refracted through the crystals' 60-degree prisms, its share h
 * firmament's choice: a ring 1.3 times as bright as the sky just inside it (smooth crystals make
 * bright halos, rough and irregular ones none).  The total asymmetry, 0.776, lies in the 0.74-0.80 of
 * ray-traced habit mixtures and in-situ cirrus (Baum et al. 2005, J. Appl. Meteor. 44, 1896; Garrett
 * et al. 2003, GRL 30, 2132). */
#define ICE_F 0.96
#define ICE_G1 0.823
#define ICE_G2 0.50
#define ICE_HALO 0.05

double cloud_ice_phase(double cos_theta)
{
    double lobes = ICE_F * phase_hg_eval(cos_theta, ICE_G1) + (1.0 - ICE_F) * phase_hg_eval(cos_theta, -ICE_G2);
    return (1.0 - ICE_HALO) * lobes + ICE_HALO * ice_halo_phase(cos_theta);
}

double cloud_ice_asymmetry(void)
{
    return (1.0 - ICE_HALO) * (ICE_F * ICE_G1 - (1.0 - ICE_F) * ICE_G2) + ICE_HALO * ice_halo_asymmetry();
}

/* m = n - ik of liquid water at lambda_nm, linear between the table's rows. */
static double complex water_index(double lambda_nm)
{
    double um = lambda_nm * 1e-3;
    int i = 0;
    while (i + 2 < FM_WATER_INDEX_COUNT && fm_water_index[i + 1][0] < um)
        i++;
    double t = (um - fm_water_index[i][0]) / (fm_water_index[i + 1][0] - fm_water_index[i][0]);
    double n = fm_water_index[i][1] + t * (fm_water_index[i + 1][1] - fm_water_index[i][1]);
    double k = fm_water_index[i][2] + t * (fm_water_index[i + 1][2] - fm_water_index[i][2]);
    return n - k * I;
}

fm_status cloud_water_optics(const cloud_type *t, double lambda_nm, mie_lognormal_result *out, double *phase,
                             fm_error *err)
{
    double mu[CLOUD_ANGLE_COUNT] = {0};
    int n_mu = phase ? CLOUD_ANGLE_COUNT : 0;
    for (int j = 0; j < n_mu; j++)
        mu[j] = cos(cloud_angle_rad(j));
    if (!(lambda_nm >= 250.0 && lambda_nm <= 1250.0))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cloud optics cover 250-1250 nm, not %g nm", lambda_nm);
    if (t->ice || mie_modified_gamma(&t->size, lambda_nm * 1e-3, water_index(lambda_nm), NULL, n_mu, mu, phase, out))
        return fm_fail(err, FM_ERR_INTERNAL, "Mie integration failed for cloud type '%s'", t->name);
    return FM_OK;
}

fm_status cloud_tau_from_lwp(const cloud_type *t, double lwp_gm2, double *tau550, fm_error *err)
{
    if (t->ice)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "'%s' is an ice cloud: give its optical depth, not a liquid water path",
                       t->name);
    mie_lognormal_result r;
    fm_status s = cloud_water_optics(t, 550.0, &r, NULL, err);
    if (s)
        return s;
    double volume_m3 = modified_gamma_mean_volume_um3(&t->size) * 1e-18;
    *tau550 = lwp_gm2 * 1e-3 * r.ext_m2 / (CLOUD_WATER_DENSITY * volume_m3);
    return FM_OK;
}
