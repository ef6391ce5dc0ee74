#include "atmosphere/atmosphere.h"

#include "atmosphere/ozone.h"
#include "atmosphere/rayleigh.h"
#include "atmosphere/standard_atmosphere.h"
#include "base/exp_array.h"
#include "base/status.h"
#include "base/units.h"

#include <math.h>
#include <string.h>

static double molecules_density(void *ctx, double altitude_m)
{
    return us76_number_density(altitude_m);
}

typedef struct ozone_layer {
    double column_du;
    ozone_profile shape;
} ozone_layer;

static double ozone_density(void *ctx, double altitude_m)
{
    const ozone_layer *o = ctx;
    return o->column_du * ozone_profile_density_per_du(o->shape, altitude_m);
}

/* Shell boundaries (km): fine where the density changes fastest, around the ozone layer and at the
 * altitudes where aerosol layers usually end; coarser beyond 100 km for taller custom atmospheres.
 * The list is cut at the top of the atmosphere, whatever it is. */
static const double shell_altitude_km[] = {0.5, 1, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 10, 12, 14, 16, 18, 20, 22,
                                           24, 26, 28, 30, 33, 36, 40, 45, 50, 60, 70, 80, 100, 150, 200, 300,
                                           500, 1000, 2000, 5000};
#define N_SHELL_ALTITUDES ((int)(sizeof shell_altitude_km / sizeof shell_altitude_km[0]))
_Static_assert(N_SHELL_ALTITUDES + 1 <= FM_MAX_SHELLS, "shell list longer than FM_MAX_SHELLS");

fm_status atmosphere_init_clear_sky(atmosphere *atm, const spectral_grid *grid, double ozone_column_du,
                                    ozone_profile ozone_shape, double ground_albedo, fm_error *err)
{
    memset(atm, 0, sizeof *atm);
    atm->bottom_radius_m = FM_EARTH_RADIUS_M;
    atm->top_radius_m = FM_EARTH_RADIUS_M + FM_ATMOSPHERE_HEIGHT_M;
    atm->grid = *grid;
    for (int k = 0; k < grid->count; k++)
        atm->ground_albedo[k] = ground_albedo;

    species *mol = atmosphere_new_species(atm, 1);
    mol->name = "molecules";
    mol->phase.kind = PHASE_RAYLEIGH;
    for (int k = 0; k < grid->count; k++) {
        mol->sigma_s[k] = rayleigh_cross_section_m2(grid->lambda_nm[k]);
        mol->phase.param[k] = rayleigh_gamma(grid->lambda_nm[k]);
    }
    if (profile_sample(&mol->profile, molecules_density, NULL, FM_ATMOSPHERE_HEIGHT_M, FM_PROFILE_SPACING_M))
        goto oom;

    if (ozone_column_du > 0.0) {
        species *o3 = atmosphere_new_species(atm, 0);
        o3->name = "ozone";
        o3->phase.kind = PHASE_NONE;
        double t_eff = ozone_profile_effective_temperature_k(ozone_shape);
        ozone_layer layer = {ozone_column_du, ozone_shape};
        for (int k = 0; k < grid->count; k++)
            o3->sigma_a[k] = ozone_cross_section_m2(grid->lambda_nm[k], t_eff);
        if (profile_sample(&o3->profile, ozone_density, &layer, FM_ATMOSPHERE_HEIGHT_M,
                           FM_PROFILE_SPACING_M))
            goto oom;
    }
    atmosphere_update_majorants(atm);
    return FM_OK;
oom:
    atmosphere_free(atm);
    return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory while building the atmosphere");
}

void atmosphere_free(atmosphere *atm)
{
    for (int c = 0; c < atm->species_count; c++) {
        profile_free(&atm->species[c].profile);
        phase_free(&atm->species[c].phase);
    }
    atm->species_count = 0;
}

species *atmosphere_new_species(atmosphere *atm, int scatters)
{
    if (atm->species_count >= FM_MAX_SPECIES)
        return NULL;
    int at = scatters ? atm->scattering_count++ : atm->species_count;
    memmove(&atm->species[at + 1], &atm->species[at], sizeof(species) * (size_t)(atm->species_count - at));
    atm->species_count++;
    memset(&atm->species[at], 0, sizeof(species));
    return &atm->species[at];
}

/* Where a species' profile bends sharply: the nodes whose second difference exceeds a tenth of
 * the local density, i.e. the ends of the steps at an aerosol layer's bottom and top (sampled as
 * ramps over one or two 50 m cells).  The profile is linear between nodes, and smooth profiles bend
 * by far less per node (an exponential of 1 km scale height by 0.25%), so these are the kinks that
 * a Gauss rule across them would miss: a 2 km piece with the stratospheric layer's top inside (35
 * km, no fixed breakpoint there) put grazing columns 0.8% off with 8 points. */
#define EDGE_BEND 0.1

static void add_edge(atmosphere *atm, double z_m, double top_m)
{
    if (!(z_m > 0.0 && z_m < top_m) || atm->edge_count == FM_MAX_EDGES)
        return;
    for (int i = 0; i < atm->edge_count; i++)
        if (atm->edge_altitude_m[i] == z_m)
            return;
    atm->edge_altitude_m[atm->edge_count++] = z_m;
}

static void find_profile_edges(atmosphere *atm)
{
    const double top_m = atm->top_radius_m - atm->bottom_radius_m;
    atm->edge_count = 0;
    for (int c = 0; c < atm->species_count; c++) {
        const density_profile *p = &atm->species[c].profile;
        for (int i = 1; i + 1 < p->count; i++) {
            double bend = fabs(p->n[i - 1] - 2.0 * p->n[i] + p->n[i + 1]);
            double local = fmax(p->n[i - 1], fmax(p->n[i], p->n[i + 1]));
            if (bend > EDGE_BEND * local)
                add_edge(atm, i * p->dz_m, top_m);
        }
        /* profile_density is 0 above the top node */
        if (p->count > 0 && p->n[p->count - 1] != 0.0)
            add_edge(atm, (p->count - 1) * p->dz_m, top_m);
    }
}

void atmosphere_update_majorants(atmosphere *atm)
{
    find_profile_edges(atm);
    atm->profile_dz_m = atm->species_count > 0 ? atm->species[0].profile.dz_m : 0.0;
    for (int c = 1; c < atm->species_count; c++)
        if (atm->species[c].profile.dz_m != atm->profile_dz_m)
            atm->profile_dz_m = 0.0;
    const double top_m = atm->top_radius_m - atm->bottom_radius_m;
    int n = 0;
    atm->shell_radius[0] = atm->bottom_radius_m;
    for (int i = 0; i < N_SHELL_ALTITUDES && shell_altitude_km[i] * FM_KM < top_m * (1.0 - 1e-9); i++)
        atm->shell_radius[++n] = atm->bottom_radius_m + shell_altitude_km[i] * FM_KM;
    atm->shell_radius[++n] = atm->top_radius_m;
    atm->shell_count = n;
    for (int i = 0; i < n; i++) {
        double z0 = atm->shell_radius[i] - atm->bottom_radius_m;
        double z1 = atm->shell_radius[i + 1] - atm->bottom_radius_m;
        /* a little headroom against rounding in the interpolation */
        for (int c = 0; c < atm->species_count; c++)
            atm->shell_density_max[i][c] = profile_max(&atm->species[c].profile, z0, z1) * (1.0 + 1e-9);
    }
    for (int c = 0; c < atm->species_count; c++)
        for (int k = 0; k < atm->grid.count; k++)
            atm->species_sigma_t[c][k] = atm->species[c].sigma_s[k] + atm->species[c].sigma_a[k];
    for (int i = 0; i < n; i++)
        atmosphere_optical_depths(atm, atm->shell_density_max[i], atm->shell_majorant[i]);
}

void atmosphere_coefficients(const atmosphere *atm, double r, double *sigma_s, double *sigma_t)
{
    double n[FM_MAX_SPECIES];
    atmosphere_densities(atm, r, n);
    atmosphere_coefficients_from_densities(atm, n, sigma_s, sigma_t);
}

/* The spectral loops below take each species' density or column into a local and write through
 * restrict pointers: without them every product reloads it (the output might overwrite it) and the
 * loops stay scalar. */
void atmosphere_coefficients_from_densities(const atmosphere *atm, const double *n, double *restrict sigma_s,
                                            double *restrict sigma_t)
{
    const int K = atm->grid.count;
    for (int k = 0; k < K; k++)
        sigma_s[k] = sigma_t[k] = 0.0;
    /* species by species, skipping the absent ones (aerosol layers exist only in their altitude
     * range); the sums per wavelength run over species in a fixed order */
    for (int c = 0; c < atm->species_count; c++) {
        const double nc = n[c];
        if (nc == 0.0)
            continue;
        const double *s = atm->species[c].sigma_s, *t = atm->species_sigma_t[c];
        for (int k = 0; k < K; k++) {
            sigma_s[k] += s[k] * nc;
            sigma_t[k] += t[k] * nc;
        }
    }
}

void atmosphere_optical_depths(const atmosphere *atm, const double *columns, double *restrict depth)
{
    const int K = atm->grid.count;
    for (int k = 0; k < K; k++)
        depth[k] = 0.0;
    for (int c = 0; c < atm->species_count; c++) {
        const double col = columns[c];
        if (col == 0.0)
            continue;
        const double *sigma = atm->species_sigma_t[c];
        for (int k = 0; k < K; k++)
            depth[k] += sigma[k] * col;
    }
}

void atmosphere_transmittances(const atmosphere *atm, const double *columns, double *T)
{
    const int K = atm->grid.count;
    atmosphere_optical_depths(atm, columns, T);
    for (int k = 0; k < K; k++)
        T[k] = -T[k];
    exp_array(T, T, K);
}
