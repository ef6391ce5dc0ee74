/* Generates core/src/data/aerosol_optics_opac.c: Mie optics per particle of every OPAC component
 * (data/opac_components.c) on firmament's wavelength grid, with tabulated phase functions.
 *
 *     make-aerosol-tables [OUTPUT.c] [THREADS] [--spot-check]   (scripts/make-aerosol-tables runs it)
 *
 * --spot-check computes one wavelength per component (wavelength index 7 e mod W for component e,
 * so the 38 components visit most of the grid) and writes zeros for everything else: the test of
 * the stored table (tests/physics/test_aerosol_tables.c) regenerates those in seconds, not minutes.
 *
 * Method: aerosol/mie_lognormal.c at each wavelength 300, 320, ..., 1000 nm, the refractive index
 * interpolated linearly in wavelength between OPAC's tabulated ones.  The phase function is
 * evaluated on a grid six times denser (in the quadratic angle index) over the first
 * FORWARD_INTERVALS intervals, where the diffraction peak of coarse particles is narrower than the
 * table's spacing, and stored as its average over each node's hat function in cos(theta): the
 * piecewise-linear table then integrates to the exact Mie normalisation.  Deterministic: every
 * (component, wavelength) is computed alone, whichever thread runs it. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "aerosol/aerosol_optics.h"
#include "aerosol/mie_lognormal.h"
#include "base/threads.h"
#include "base/units.h"
#include "data/tables.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define A AEROSOL_ANGLE_COUNT
#define W AEROSOL_WAVELENGTH_COUNT
#define REFINE 6
/* intervals refined: theta below pi (40/300)^2 = 3.2 degrees at A = 301 */
#define FORWARD_INTERVALS ((A - 1) * 2 / 15)
#define FINE_COUNT (REFINE * FORWARD_INTERVALS + (A - 1 - FORWARD_INTERVALS) + 1)

typedef struct fine_grid {
    double theta[FINE_COUNT], mu[FINE_COUNT];
    int coarse[FINE_COUNT]; /* coarse interval j (between nodes j and j + 1) the node starts */
} fine_grid;

typedef struct job {
    int spot_check;
    fine_grid grid;
    double coarse_theta[A];
    aerosol_optics *out;
    int failed;
} job;

static void make_grid(job *jb)
{
    fine_grid *g = &jb->grid;
    int f = 0;
    for (int s = 0; s < REFINE * FORWARD_INTERVALS; s++, f++) {
        double t = (double)s / (REFINE * (A - 1));
        g->theta[f] = FM_PI * t * t;
        g->coarse[f] = s / REFINE;
    }
    for (int j = FORWARD_INTERVALS; j < A; j++, f++) {
        g->theta[f] = aerosol_optics_angle_rad(j);
        g->coarse[f] = j;
    }
    for (int i = 0; i < FINE_COUNT; i++)
        g->mu[i] = cos(g->theta[i]);
    for (int j = 0; j < A; j++)
        jb->coarse_theta[j] = aerosol_optics_angle_rad(j);
}

/* cos(a) - cos(b) without cancellation near the forward direction */
static double cos_difference(double a, double b)
{
    return 2.0 * sin(0.5 * (a + b)) * sin(0.5 * (b - a));
}

/* Hat-function averages over the coarse nodes of the piecewise-linear fine phase function. */
static void hat_average(const job *jb, const double *fine, float *coarse)
{
    double num[A] = {0}, den[A] = {0};
    const fine_grid *g = &jb->grid;
    for (int i = 0; i + 1 < FINE_COUNT; i++) {
        int j = g->coarse[i];
        double ta = jb->coarse_theta[j], tb = jb->coarse_theta[j + 1];
        double h = cos_difference(ta, tb);
        /* hat of node j at the fine segment's ends (1 at node j, 0 at node j + 1) */
        double phi_a = cos_difference(g->theta[i], tb) / h, phi_b = cos_difference(g->theta[i + 1], tb) / h;
        double dmu = cos_difference(g->theta[i], g->theta[i + 1]);
        double pa = fine[i], pb = fine[i + 1];
        double with_j = dmu * (pa * phi_a / 3.0 + pa * phi_b / 6.0 + pb * phi_a / 6.0 + pb * phi_b / 3.0);
        double all = dmu * 0.5 * (pa + pb);
        num[j] += with_j;
        num[j + 1] += all - with_j;
        den[j] += 0.5 * dmu * (phi_a + phi_b);
        den[j + 1] += dmu - 0.5 * dmu * (phi_a + phi_b);
    }
    for (int j = 0; j < A; j++)
        coarse[j] = (float)(num[j] / den[j]);
}

/* m = n - ik at lambda_um, linear in wavelength between OPAC's rows. */
static double complex opac_index(const fm_opac_component *c, double lambda_um)
{
    int i = 0;
    while (i + 2 < FM_OPAC_REFR_COUNT && c->refr[i + 1][0] < lambda_um)
        i++;
    double t = (lambda_um - c->refr[i][0]) / (c->refr[i + 1][0] - c->refr[i][0]);
    double n = c->refr[i][1] + t * (c->refr[i + 1][1] - c->refr[i][1]);
    double k = c->refr[i][2] + t * (c->refr[i + 1][2] - c->refr[i][2]);
    return n - k * I;
}

static void run_items(void *ctx, int64_t begin, int64_t end, int thread)
{
    job *jb = ctx;
    double fine[FINE_COUNT];
    for (int64_t item = begin; item < end; item++) {
        int e = (int)(item / W), i = (int)(item % W);
        if (jb->spot_check && i != AEROSOL_SPOT_WAVELENGTH(e))
            continue;
        const fm_opac_component *c = &fm_opac_components[e];
        lognormal_size size = {c->r_mod_um, c->sigma, c->r_min_um, c->r_max_um};
        double lambda_um = aerosol_optics_wavelength_nm(i) * 1e-3;
        mie_lognormal_result r;
        if (mie_lognormal(&size, lambda_um, opac_index(c, lambda_um), NULL, FINE_COUNT, jb->grid.mu, fine, &r) != 0) {
            jb->failed = 1;
            continue;
        }
        aerosol_optics *o = &jb->out[e];
        o->ext_m2[i] = r.ext_m2;
        o->sca_m2[i] = r.sca_m2;
        o->g[i] = r.g;
        hat_average(jb, fine, o->phase[i]);
    }
}

static void write_values(FILE *f, const char *indent, int count, const double *v, const float *fv)
{
    for (int i = 0; i < count; i++) {
        if (i % 8 == 0)
            fprintf(f, "%s%s", i ? "\n" : "", indent);
        fprintf(f, "%.6g,%s", fv ? (double)fv[i] : v[i], i % 8 == 7 || i == count - 1 ? "" : " ");
    }
    fprintf(f, "\n");
}

static int write_table(const char *path, const aerosol_optics *t)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f,
            "/* Optical properties per particle of the OPAC aerosol components (generated, do not edit:\n"
            " * scripts/make-aerosol-tables rebuilds it with tools/aerosol_tables.c).\n"
            " *\n"
            " * Microphysics: OPAC log-normal size distributions and refractive indices, data/opac_components.c\n"
            " * (M. Hess, P. Koepke, I. Schult, Bull. Amer. Meteor. Soc. 79 (1998) 831-844; files\n"
            " * size_distr.cfg, refractive_indices/ and the optdat/ headers of the OPAC distribution).\n"
            " * Method: Lorenz-Mie theory for homogeneous spheres (aerosol/mie.c) integrated over the size\n"
            " * distribution truncated to [r_min, r_max], normalised to one particle of the full distribution\n"
            " * (aerosol/mie_lognormal.c); index interpolated linearly in wavelength.\n"
            " * Units: ext_m2, sca_m2 in m^2 per particle; g dimensionless; phase in sr^-1 at\n"
            " * theta_j = pi (j / %d)^2, hat-function averages in cos(theta) (see aerosol/aerosol_optics.h).\n"
            " * Wavelengths 300, 320, ..., 1000 nm. */\n\n"
            "#include \"aerosol/aerosol_optics.h\"\n\n"
            "const aerosol_optics aerosol_optics_table[] = {\n",
            A - 1);
    for (int e = 0; e < FM_OPAC_COMPONENT_COUNT; e++) {
        fprintf(f, "    {\"%s\", %d,\n", t[e].component, t[e].humidity_percent);
        fprintf(f, "     {\n");
        write_values(f, "      ", W, t[e].ext_m2, NULL);
        fprintf(f, "     },\n     {\n");
        write_values(f, "      ", W, t[e].sca_m2, NULL);
        fprintf(f, "     },\n     {\n");
        write_values(f, "      ", W, t[e].g, NULL);
        fprintf(f, "     },\n     {\n");
        for (int i = 0; i < W; i++) {
            fprintf(f, "      { /* %g nm */\n", aerosol_optics_wavelength_nm(i));
            write_values(f, "       ", A, NULL, t[e].phase[i]);
            fprintf(f, "      },\n");
        }
        fprintf(f, "     }},\n");
    }
    fprintf(f, "};\n\nconst int aerosol_optics_count = %d;\n", FM_OPAC_COMPONENT_COUNT);
    return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "core/src/data/aerosol_optics_opac.c";
    int threads = argc > 2 ? atoi(argv[2]) : 2;
    static job jb;
    jb.spot_check = argc > 3 && strcmp(argv[3], "--spot-check") == 0;
    make_grid(&jb);
    jb.out = calloc(FM_OPAC_COMPONENT_COUNT, sizeof *jb.out);
    if (!jb.out)
        return 1;
    for (int e = 0; e < FM_OPAC_COMPONENT_COUNT; e++) {
        jb.out[e].component = fm_opac_components[e].code;
        jb.out[e].humidity_percent = fm_opac_components[e].humidity_percent;
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    fm_status st = parallel_for(threads, (int64_t)FM_OPAC_COMPONENT_COUNT * W, 1, run_items, &jb, NULL, NULL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (st != FM_OK || jb.failed) {
        fprintf(stderr, "make-aerosol-tables: Mie integration failed\n");
        return 1;
    }
    double worst_norm = 0.0, worst_g = 0.0;
    for (int e = 0; e < FM_OPAC_COMPONENT_COUNT; e++)
        for (int i = 0; i < W; i++) {
            if (jb.spot_check && i != AEROSOL_SPOT_WAVELENGTH(e))
                continue;
            double mc, norm = aerosol_phase_integral(jb.out[e].phase[i], &mc);
            if (fabs(norm - 1.0) > worst_norm)
                worst_norm = fabs(norm - 1.0);
            if (fabs(mc - jb.out[e].g[i]) > worst_g)
                worst_g = fabs(mc - jb.out[e].g[i]);
        }
    if (write_table(path, jb.out) != 0) {
        fprintf(stderr, "make-aerosol-tables: cannot write %s\n", path);
        return 1;
    }
    printf("wrote %s: %d entries x %d wavelengths x %d angles in %.1f s on %d threads\n", path,
           FM_OPAC_COMPONENT_COUNT, W, A,
           (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec), threads);
    printf("tabulated phase functions: worst |integral - 1| = %.2e, worst |<cos> - g| = %.2e\n", worst_norm,
           worst_g);
    free(jb.out);
    return 0;
}
