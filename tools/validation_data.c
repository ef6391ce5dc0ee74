/* Numbers for the validation report (tests/validate): writes CSV files into the directory given.
 *
 *   profiles.csv        radiance along the solar almucantar and the solar vertical (rural aerosol,
 *                       sun 30 deg), fast path from a map at four wavelengths, and per-direction
 *                       reference-mode estimates with their standard errors at a few angles
 *   zenith_spectra.csv  spectral zenith radiance for three biomes (sun 30 deg)
 *   direct_spectra.csv  direct normal spectral irradiance of the same skies (monochromatic skies
 *                       every 20 nm)
 *   illuminance.csv     direct, diffuse and global horizontal illuminance against sun elevation
 *   aod_spectra.csv     vertical aerosol optical depth of every biome at the colour grid's wavelengths
 *
 *   validation_data OUT_DIR [--quick]
 *
 * Only the public API, except for the aerosol optical depth per wavelength, which reads the built
 * atmosphere's species (as tests/physics/test_aerosol.c does). */
#include "firmament/firmament.h"
#include "sky.h"

#include "base/units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const biomes[] = {"background", "desert-dust", "maritime-clean", "maritime-mineral",
                                     "polar-antarctic", "polar-arctic", "remote-continental", "rural", "urban"};

static void die(const char *what, const fm_error *err)
{
    fprintf(stderr, "validation_data: %s: %s\n", what, err ? err->message : "failed");
    exit(1);
}

static fm_sky *make_sky(double sun_elevation_deg, double lambda_nm, const char *biome_name)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = sun_elevation_deg;
    p.sun_azimuth_deg = 180.0;
    p.wavelength_nm = lambda_nm;
    p.biome = biome_name;
    fm_sky *sky = NULL;
    fm_error err;
    if (fm_sky_create(&p, &sky, &err))
        die("sky", &err);
    return sky;
}

static fm_image *render(const fm_sky *sky, const fm_camera *cam, int width, fm_quality q, int samples, int spectral)
{
    fm_render_params rp = fm_render_params_default();
    rp.width = width;
    rp.quality = q;
    rp.reference_samples = samples;
    rp.sun_disk = 0;
    rp.spectral = spectral;
    if (cam)
        rp.camera = *cam;
    fm_image *img = NULL;
    fm_error err;
    if (fm_render(sky, &rp, &img, &err))
        die("render", &err);
    return img;
}

static FILE *open_csv(const char *dir, const char *name, const char *header)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "validation_data: cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "%s\n", header);
    return f;
}

/* Bilinear value of a one-channel equirect map at (elevation, azimuth) in degrees. */
static double map_value(const fm_image *m, double elevation_deg, double azimuth_deg)
{
    double u = 0.25 + azimuth_deg / 360.0, v = 0.5 - elevation_deg / 180.0;
    double x = u * m->width - 0.5, y = v * m->height - 0.5;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0, sum = 0.0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xi = ((x0 + i) % m->width + m->width) % m->width;
            int yj = y0 + j < 0 ? 0 : (y0 + j >= m->height ? m->height - 1 : y0 + j);
            sum += (i ? fx : 1 - fx) * (j ? fy : 1 - fy) * m->pixels[(size_t)yj * m->width + xi];
        }
    return sum;
}

/* Reference-mode radiance toward (elevation, azimuth): the mean of an 8 x 8 pinhole view 0.4 deg
 * wide, with the standard error of that mean. */
static double reference_value(const fm_sky *sky, double elevation_deg, double azimuth_deg, int samples, double *se)
{
    fm_camera c = fm_render_params_default().camera;
    c.type = FM_CAMERA_PINHOLE;
    c.fov_deg = 0.4;
    c.aspect = 1.0;
    c.look_azimuth_deg = azimuth_deg;
    c.look_elevation_deg = elevation_deg;
    fm_image *img = render(sky, &c, 8, FM_QUALITY_REFERENCE, samples, 0);
    double sum = 0.0, var = 0.0;
    int n = img->width * img->height;
    for (int i = 0; i < n; i++) {
        sum += img->pixels[i];
        var += (double)img->std_error[i] * img->std_error[i];
    }
    fm_image_destroy(img);
    *se = sqrt(var) / n;
    return sum / n;
}

static void profiles(const char *dir, int quick)
{
    FILE *f = open_csv(dir, "profiles.csv", "wavelength_nm,curve,angle_deg,fast,reference,reference_se");
    const double sun_el = 30.0, lambdas[4] = {400, 500, 600, 700};
    const int samples = quick ? 32 : 512;
    for (int l = 0; l < 4; l++) {
        fm_sky *sky = make_sky(sun_el, lambdas[l], "rural");
        fm_image *map = render(sky, NULL, 1024, FM_QUALITY_FINAL, 0, 0);
        /* almucantar: the sun's elevation, angle = azimuth from the sun */
        for (double a = 0.0; a <= 180.0 + 1e-9; a += 1.0) {
            double ref = NAN, se = NAN;
            if (fmod(a, quick ? 60.0 : 20.0) == 0.0 && a >= 20.0)
                ref = reference_value(sky, sun_el, 180.0 + a, samples, &se);
            fprintf(f, "%g,almucantar,%g,%.6e,%.6e,%.3e\n", lambdas[l], a, map_value(map, sun_el, 180.0 + a), ref, se);
        }
        /* solar vertical: angle = scattering angle-like coordinate, view zenith measured through the
         * zenith from the sun's side (negative) to the other side (positive) */
        for (double z = -89.0; z <= 89.0 + 1e-9; z += 1.0) {
            double el = 90.0 - fabs(z), az = z < 0 ? 180.0 : 0.0;
            double ref = NAN, se = NAN;
            if (fmod(fabs(z), quick ? 60.0 : 20.0) == 10.0)
                ref = reference_value(sky, el, az, samples, &se);
            fprintf(f, "%g,vertical,%g,%.6e,%.6e,%.3e\n", lambdas[l], z, map_value(map, el, az), ref, se);
        }
        fm_image_destroy(map);
        fm_sky_destroy(sky);
        fprintf(stderr, "profiles: %g nm\n", lambdas[l]);
    }
    fclose(f);
}

static void zenith_spectra(const char *dir)
{
    FILE *f = open_csv(dir, "zenith_spectra.csv", "biome,wavelength_nm,zenith_radiance");
    const char *names[3] = {"none", "rural", "urban"};
    for (int b = 0; b < 3; b++) {
        fm_sky *sky = make_sky(30.0, 0.0, names[b]);
        fm_image *img = render(sky, NULL, 128, FM_QUALITY_FINAL, 0, 1);
        for (int k = 0; k < img->wavelengths; k++) {
            /* the zenith: the mean of the top row, which covers the cap above 88.6 deg */
            double z = 0.0;
            for (int x = 0; x < img->width; x++)
                z += img->pixels[(size_t)x * img->channels + k];
            z /= img->width;
            fprintf(f, "%s,%g,%.6e\n", names[b], img->lambda_nm[k], z);
        }
        fm_image_destroy(img);
        fm_sky_destroy(sky);
    }
    fclose(f);
    fprintf(stderr, "zenith spectra\n");
}

static void direct_spectra(const char *dir)
{
    FILE *f = open_csv(dir, "direct_spectra.csv", "biome,wavelength_nm,direct_normal_irradiance");
    const char *names[3] = {"none", "rural", "urban"};
    for (int b = 0; b < 3; b++)
        for (double nm = 380.0; nm <= 780.0; nm += 20.0) {
            fm_sky *sky = make_sky(30.0, nm, names[b]);
            fm_sun_light sun;
            fm_sky_sun_light(sky, &sun);
            fprintf(f, "%s,%g,%.6e\n", names[b], nm, sun.normal_irradiance[0]);
            fm_sky_destroy(sky);
        }
    fclose(f);
    fprintf(stderr, "direct spectra\n");
}

static void illuminance(const char *dir, int quick)
{
    FILE *f = open_csv(dir, "illuminance.csv",
                       "biome,sun_elevation_deg,direct_horizontal_lux,diffuse_horizontal_lux,global_horizontal_lux");
    const char *names[2] = {"rural", "urban"};
    for (int b = 0; b < 2; b++)
        for (int i = 0; i < 20; i += quick ? 3 : 1) {
            const double elevations[20] = {-18, -15, -12, -9, -6, -4, -2, 0, 2, 4, 6, 8, 10, 15, 20, 30, 45, 60, 75, 90};
            double e = elevations[i];
            fm_sky *sky = make_sky(e, 0.0, names[b]);
            fm_sun_light sun;
            fm_sky_sun_light(sky, &sun);
            fm_image *img = render(sky, NULL, 64, FM_QUALITY_PREVIEW, 0, 0);
            double diffuse[3];
            fm_image_diffuse_horizontal(img, diffuse);
            double direct = FM_LUMINOUS_EFFICACY * sun.horizontal_irradiance[1];
            double sky_lux = FM_LUMINOUS_EFFICACY * diffuse[1];
            fprintf(f, "%s,%g,%.6e,%.6e,%.6e\n", names[b], e, direct, sky_lux, direct + sky_lux);
            fm_image_destroy(img);
            fm_sky_destroy(sky);
        }
    fclose(f);
    fprintf(stderr, "illuminance\n");
}

static void aod_spectra(const char *dir)
{
    FILE *f = open_csv(dir, "aod_spectra.csv", "biome,wavelength_nm,aerosol_optical_depth,reported_aod550");
    for (size_t b = 0; b < sizeof biomes / sizeof biomes[0]; b++) {
        fm_sky *sky = make_sky(30.0, 0.0, biomes[b]);
        fm_composition comp;
        fm_sky_composition(sky, &comp);
        for (int k = 0; k < sky->atm.grid.count; k++) {
            double tau = 0.0;
            for (int c = 0; c < sky->atm.species_count; c++)
                if (!strcmp(sky->atm.species[c].name, "aerosol"))
                    tau += (sky->atm.species[c].sigma_s[k] + sky->atm.species[c].sigma_a[k]) *
                           profile_column(&sky->atm.species[c].profile);
            fprintf(f, "%s,%g,%.6e,%.6e\n", biomes[b], sky->atm.grid.lambda_nm[k], tau, comp.aerosol_tau550);
        }
        fm_sky_destroy(sky);
    }
    fclose(f);
    fprintf(stderr, "aod spectra\n");
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3 || (argc == 3 && strcmp(argv[2], "--quick"))) {
        fprintf(stderr, "usage: validation_data OUT_DIR [--quick]\n");
        return 2;
    }
    int quick = argc == 3;
    profiles(argv[1], quick);
    aod_spectra(argv[1]);
    zenith_spectra(argv[1]);
    direct_spectra(argv[1]);
    illuminance(argv[1], quick);
    return 0;
}
