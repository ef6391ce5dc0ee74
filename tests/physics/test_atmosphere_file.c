/* Custom atmosphere files: the four reference atmospheres (after E. Bruneton's 2017 demo) build the
 * coefficients they state, a file restating the built-in molecular atmosphere renders the built-in
 * sky, and malformed files are refused with the file, the JSON path and the problem. */
#include "check.h"

#include "atmosphere/atmosphere_file.h"
#include "atmosphere/optical_depth.h"
#include "atmosphere/rayleigh.h"
#include "base/units.h"
#include "phase/phase_rayleigh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PRESETS FM_SOURCE_DIR "/presets/atmospheres/"
#define FIXTURE FM_SOURCE_DIR "/tests/data/molecular-us76.json"

static const species *find_species(const atmosphere *atm, const char *name)
{
    for (int c = 0; c < atm->species_count; c++)
        if (strcmp(atm->species[c].name, name) == 0)
            return &atm->species[c];
    fail_msg("no species '%s'", name);
    return NULL;
}

/* Extinction, scattering coefficients (m^-1) of one species at altitude z for grid wavelength 0. */
static double species_ext(const species *sp, double z)
{
    return (sp->sigma_s[0] + sp->sigma_a[0]) * profile_density(&sp->profile, z);
}
static double species_sca(const species *sp, double z)
{
    return sp->sigma_s[0] * profile_density(&sp->profile, z);
}

static void load(atmosphere *atm, const char *path, double lambda_nm, double solar_scale, double albedo)
{
    spectral_grid grid;
    if (lambda_nm > 0.0)
        spectral_grid_single(&grid, lambda_nm);
    else
        spectral_grid_visible(&grid);
    fm_error err = {0};
    if (atmosphere_init_from_file(atm, path, &grid, solar_scale, albedo, &err) != FM_OK)
        fail_msg("%s", err.message);
}

/* Bruneton's demo values at 440 / 550 / 680 nm (the table). */
static const double lambdas[3] = {440.0, 550.0, 680.0};
static const double rayleigh_beta[3] = {33.1e-6, 13.5e-6, 5.8e-6};
static const double ozone_beta[3] = {0.085e-6, 1.881e-6, 0.650e-6};
#define AEROSOL_EXT 4.44e-6

static void check_molecules(const atmosphere *atm, int i)
{
    const species *m = find_species(atm, "molecules");
    check_rel(species_sca(m, 0.0), rayleigh_beta[i], 1e-12, "Rayleigh at sea level");
    check_rel(species_sca(m, 8000.0), rayleigh_beta[i] * exp(-1.0), 1e-12, "Rayleigh at one scale height");
    /* between profile nodes: the 50 m piecewise-linear profile is within 3e-6 of the exponential */
    check_rel(species_sca(m, 8025.0), rayleigh_beta[i] * exp(-8025.0 / 8000.0), 5e-6, "Rayleigh at 8.025 km");
    check_rel(species_sca(m, 59990.0), rayleigh_beta[i] * exp(-59990.0 / 8000.0), 5e-6, "Rayleigh near the top");
    assert_true(m->sigma_a[0] == 0.0);
    assert_int_equal(m->phase.kind, PHASE_RAYLEIGH);
    assert_true(m->phase.param[0] == 0.0); /* depolarisation 0: gamma 0 */
}

static void reference_atmospheres_build_their_coefficients(void **state)
{
    const char *names[4] = {"reference-rayleigh", "reference-rayleigh-ozone", "reference-rayleigh-aerosol",
                            "reference-rayleigh-aerosol-albedo"};
    for (int f = 0; f < 4; f++) {
        char path[512];
        snprintf(path, sizeof path, PRESETS "%s.json", names[f]);
        for (int i = 0; i < 3; i++) {
            atmosphere atm;
            load(&atm, path, lambdas[i], 1.0, 0.2);
            check_abs(atm.bottom_radius_m, 6360e3, 1e-6, "planet radius");
            check_abs(atm.top_radius_m, 6420e3, 1e-6, "top of the atmosphere");
            check_abs(atm.grid.solar_irradiance[0], 1.0, 0.0, "solar irradiance (file value, 1 AU)");
            check_abs(atm.ground_albedo[0], f == 3 ? 0.3 : 0.0, 0.0, "ground albedo (the file's, not 0.2)");
            check_molecules(&atm, i);
            if (f == 1) {
                assert_int_equal(atm.species_count, 2);
                assert_int_equal(atm.scattering_count, 1);
                const species *o = find_species(&atm, "ozone");
                assert_true(o->sigma_s[0] == 0.0);
                assert_int_equal(o->phase.kind, PHASE_NONE);
                check_rel(species_ext(o, 25000.0), ozone_beta[i], 1e-12, "ozone at the tent's peak");
                check_rel(species_ext(o, 17500.0), 0.5 * ozone_beta[i], 1e-12, "ozone tent at 17.5 km");
                check_rel(species_ext(o, 32500.0), 0.5 * ozone_beta[i], 1e-12, "ozone tent at 32.5 km");
                check_abs(species_ext(o, 5000.0), 0.0, 0.0, "no ozone below 10 km");
                check_abs(species_ext(o, 45000.0), 0.0, 0.0, "no ozone above 40 km");
            }
            if (f >= 2) {
                assert_int_equal(atm.species_count, 2);
                assert_int_equal(atm.scattering_count, 2);
                const species *a = find_species(&atm, "aerosol");
                check_rel(species_ext(a, 0.0), AEROSOL_EXT, 1e-12, "aerosol extinction at the ground");
                check_rel(species_sca(a, 0.0), 0.9 * AEROSOL_EXT, 1e-12, "aerosol scattering = 0.9 x extinction");
                check_rel(species_ext(a, 1200.0), AEROSOL_EXT * exp(-1.0), 1e-12, "aerosol at one scale height");
                assert_int_equal(a->phase.kind, PHASE_HENYEY_GREENSTEIN);
                check_abs(a->phase.param[0], 0.8, 0.0, "Henyey-Greenstein g");
            } else if (f == 0) {
                assert_int_equal(atm.species_count, 1);
            }
            atmosphere_free(&atm);
        }
    }
    /* the file's spectrum is at 1 AU: the caller's 1/d^2 applies to it */
    atmosphere atm;
    load(&atm, PRESETS "reference-rayleigh.json", 550.0, 0.5, 0.2);
    check_abs(atm.grid.solar_irradiance[0], 0.5, 0.0, "file spectrum x solar_scale");
    atmosphere_free(&atm);
}

/* Vertical optical depth of reference-rayleigh at 550 nm: 13.5e-6 * 8000 * (1 - exp(-60/8)). */
static void reference_rayleigh_optical_depth(void **state)
{
    atmosphere atm;
    load(&atm, PRESETS "reference-rayleigh.json", 550.0, 1.0, 0.0);
    double col[FM_MAX_SPECIES];
    column_exact(&atm, atm.bottom_radius_m, 1.0, atm.top_radius_m - atm.bottom_radius_m, col);
    double tau = atmosphere_optical_depth(&atm, col, 0);
    double expected = 13.5e-6 * 8000.0 * (1.0 - exp(-60.0 / 8.0));
    print_message("reference-rayleigh tau(550 nm) = %.8f (closed form %.8f)\n", tau, expected);
    check_rel(tau, expected, 1e-3, "vertical optical depth");
    check_rel(tau, expected, 1e-5, "vertical optical depth (50 m profile)");
    atmosphere_free(&atm);
}

/* Majorant shells for a 60 km top: ascending, ending at the top, and above the extinction. */
static void majorant_shells_follow_the_top(void **state)
{
    const char *files[2] = {PRESETS "reference-rayleigh-ozone.json", PRESETS "reference-rayleigh-aerosol.json"};
    for (int f = 0; f < 2; f++) {
        atmosphere atm;
        load(&atm, files[f], 440.0, 1.0, 0.0);
        assert_true(atm.shell_count >= 2 && atm.shell_count <= FM_MAX_SHELLS);
        check_abs(atm.shell_radius[0], atm.bottom_radius_m, 0.0, "first shell at the ground");
        check_abs(atm.shell_radius[atm.shell_count], atm.top_radius_m, 0.0, "last shell at the top");
        for (int i = 0; i < atm.shell_count; i++) {
            assert_true(atm.shell_radius[i + 1] > atm.shell_radius[i]);
            for (double r = atm.shell_radius[i]; r <= atm.shell_radius[i + 1]; r += 10.0) {
                double s, t;
                atmosphere_coefficients(&atm, r, &s, &t);
                if (t > atm.shell_majorant[i][0])
                    fail_msg("shell %d: sigma_t %g above the majorant %g at %g m", i, t, atm.shell_majorant[i][0],
                             r - atm.bottom_radius_m);
            }
        }
        atmosphere_free(&atm);
    }
}

/* The fixture restates the built-in molecules: same coefficients everywhere on the colour grid. */
static void molecular_fixture_matches_builtin_coefficients(void **state)
{
    spectral_grid grid;
    spectral_grid_visible(&grid);
    atmosphere builtin, file;
    fm_error err;
    assert_int_equal(atmosphere_init_clear_sky(&builtin, &grid, 0.0, OZONE_PROFILE_US_STANDARD, 0.2, &err), FM_OK);
    load(&file, FIXTURE, 0.0, 1.0, 0.2);
    assert_int_equal(file.species_count, 1);
    check_abs(file.top_radius_m, builtin.top_radius_m, 1e-6, "top");
    check_abs(file.bottom_radius_m, builtin.bottom_radius_m, 1e-6, "radius");
    for (int k = 0; k < grid.count; k++) {
        check_rel(file.grid.solar_irradiance[k], builtin.grid.solar_irradiance[k], 0.0, "built-in solar spectrum kept");
        check_rel(file.species[0].phase.param[k], builtin.species[0].phase.param[k], 1e-9, "Rayleigh gamma");
        check_abs(file.ground_albedo[k], 0.2, 0.0, "albedo from the parameters");
        for (double z = 0.0; z <= 100000.0; z += 1237.0) {
            double a = builtin.species[0].sigma_s[k] * profile_density(&builtin.species[0].profile, z);
            double b = file.species[0].sigma_s[k] * profile_density(&file.species[0].profile, z);
            if (fabs(a - b) > 1e-9 * a)
                fail_msg("%g nm, %g m: built-in %.10g, file %.10g", grid.lambda_nm[k], z, a, b);
        }
    }
    atmosphere_free(&builtin);
    atmosphere_free(&file);
}

/* ... and renders the built-in sky within the estimator's noise.  The noise is measured as the
 * differences between built-in renders with different seeds; the file's render (another seed) must
 * differ from the built-in one by no more than that. */
static void molecular_fixture_renders_the_builtin_sky(void **state)
{
    fm_sky_params p = test_params(20.0, 0.0);
    p.ozone_column_du = 0.0;
    fm_sky *builtin = test_sky(&p);
    p.atmosphere_file = FIXTURE;
    fm_sky *file = test_sky(&p);
    fm_image *a = test_render(builtin, 64, FM_QUALITY_FINAL, 0, 1, 0, 1.0, 0);
    fm_image *a2 = test_render(builtin, 64, FM_QUALITY_FINAL, 0, 2, 0, 1.0, 0);
    fm_image *b = test_render(file, 64, FM_QUALITY_FINAL, 0, 3, 0, 1.0, 0);
    fm_comparison noise, diff;
    fm_error err;
    assert_int_equal(fm_image_compare(a2, a, 0.0, &noise, &err), FM_OK);
    assert_int_equal(fm_image_compare(b, a, 0.0, &diff, &err), FM_OK);
    print_message("built-in vs built-in (seeds 2, 1): rms %.3e mean %+.3e max %.3e\n", noise.rms, noise.mean, noise.max);
    print_message("file vs built-in (seeds 3, 1):     rms %.3e mean %+.3e max %.3e\n", diff.rms, diff.mean, diff.max);
    assert_true(noise.pixels == 64 * 32 && diff.pixels == 64 * 32);
    /* rms of a difference of two independent renders: sqrt(2) x one render's noise; allow 30% on it */
    assert_true(diff.rms <= 1.3 * noise.rms + 1e-6);
    /* bias: the tables behind the fast path are shared by all pixels, so a render's noise has a
     * common part that moves the mean of a difference as a whole; its spread is measured by the mean
     * differences of more built-in pairs (seeds 4, 5 against 1) */
    double common2 = noise.mean * noise.mean;
    for (uint64_t seed = 4; seed <= 5; seed++) {
        fm_image *c = test_render(builtin, 64, FM_QUALITY_FINAL, 0, seed, 0, 1.0, 0);
        fm_comparison pair;
        assert_int_equal(fm_image_compare(c, a, 0.0, &pair, &err), FM_OK);
        common2 += pair.mean * pair.mean;
        fm_image_destroy(c);
    }
    double common = sqrt(common2 / 3.0); /* rms of three pairs' mean differences */
    print_message("common-mode noise of a pair: %.3e\n", common);
    assert_true(fabs(diff.mean) <= 4.0 * common + 3.0 * noise.rms / sqrt((double)diff.pixels));
    fm_image *b1 = test_render(file, 64, FM_QUALITY_FINAL, 0, 1, 0, 1.0, 0);
    fm_comparison same;
    assert_int_equal(fm_image_compare(b1, a, 0.0, &same, &err), FM_OK);
    print_message("file vs built-in (same seed 1):   rms %.3e mean %+.3e max %.3e\n", same.rms, same.mean, same.max);
    /* same random streams through the same medium (to rounding): the same map to rounding */
    assert_true(same.rms < 1e-6);
    fm_image_destroy(b1);
    /* the sun light through the file's atmosphere is the built-in one */
    fm_sun_light la, lb;
    fm_sky_sun_light(builtin, &la);
    fm_sky_sun_light(file, &lb);
    for (int j = 0; j < 3; j++)
        check_rel(lb.normal_irradiance[j], la.normal_irradiance[j], 1e-6, "direct normal irradiance");
    fm_image_destroy(a);
    fm_image_destroy(a2);
    fm_image_destroy(b);
    fm_sky_destroy(builtin);
    fm_sky_destroy(file);
}

/* ---- files written by the tests ------------------------------------------------------------- */

/* A valid file around one constituent (and optional top-level extras). */
static char *constituent_file(const char *extra_top, const char *constituent)
{
    static char text[4096];
    snprintf(text, sizeof text,
             "{\n  \"planet_radius_km\": 6360,\n  \"top_altitude_km\": 60,%s\n  \"constituents\": [\n    %s\n  ]\n}\n",
             extra_top, constituent);
    return test_write_temp("atmosphere", text);
}

static double hg(double g, double mu)
{
    return (1.0 - g * g) / (4.0 * FM_PI * pow(1.0 + g * g - 2.0 * g * mu, 1.5));
}

/* A tabulated phase function: Henyey-Greenstein g = 0.5 every degree comes back as itself; rows
 * given per wavelength (isotropic at 400 nm, that HG at 700 nm) mix linearly in between. */
static void tabulated_phase_from_a_file(void **state)
{
    static char text[16384];
    int n = snprintf(text, sizeof text,
                     "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"constituents\": [{\"profile\": "
                     "{\"type\": \"exponential\", \"scale_height_km\": 1.2}, \"scattering\": 1e-5, \"phase\": "
                     "{\"type\": \"tabulated\", \"wavelengths_nm\": [400, 700], \"angles_deg\": [");
    for (int j = 0; j <= 180; j++)
        n += snprintf(text + n, sizeof text - n, "%s%d", j ? ", " : "", j);
    n += snprintf(text + n, sizeof text - n, "], \"values\": [[");
    for (int j = 0; j <= 180; j++)
        n += snprintf(text + n, sizeof text - n, "%s1", j ? ", " : "");
    n += snprintf(text + n, sizeof text - n, "], [");
    for (int j = 0; j <= 180; j++)
        n += snprintf(text + n, sizeof text - n, "%s%.12g", j ? ", " : "", hg(0.5, cos(j * FM_DEG)));
    snprintf(text + n, sizeof text - n, "]]}}]}");
    char *path = test_write_temp("atmosphere", text);
    const double lambda[3] = {400.0, 550.0, 700.0}, weight_hg[3] = {0.0, 0.5, 1.0};
    for (int i = 0; i < 3; i++) {
        atmosphere atm;
        load(&atm, path, lambda[i], 1.0, 0.0);
        const phase_function *ph = &atm.species[0].phase;
        assert_int_equal(ph->kind, PHASE_TABULATED);
        /* g of the 1-degree piecewise-linear table: within 1e-3 of the HG value */
        check_abs(phase_asymmetry(ph, 0), 0.5 * weight_hg[i], 1e-3, "asymmetry of the tabulated phase");
        for (double t = 0.5; t < 180.0; t += 7.0) {
            double mu = cos(t * FM_DEG);
            double expected = (1.0 - weight_hg[i]) / (4.0 * FM_PI) + weight_hg[i] * hg(0.5, mu);
            check_rel(phase_evaluate(ph, 0, mu), expected, 5e-4, "tabulated phase between nodes");
        }
        atmosphere_free(&atm);
    }
    unlink(path);
    free(path);
}

/* A flat spectrum over the colour grid: E_k = 1 and the Y weights sum to the integral of ybar
 * (106.857 nm for the CIE 1931 table, 380-780 nm at 1 nm); a slope is kept at the nodes. */
static void file_solar_spectrum_on_the_colour_grid(void **state)
{
    const char *grey = "{\"name\": \"grey\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                       "\"scattering\": 1e-5, \"phase\": {\"type\": \"rayleigh\"}}";
    char *flat = constituent_file("\n  \"solar_irradiance\": 1,", grey);
    atmosphere atm;
    load(&atm, flat, 0.0, 1.0, 0.2);
    double sum_y = 0.0;
    for (int k = 0; k < atm.grid.count; k++) {
        check_abs(atm.grid.solar_irradiance[k], 1.0, 1e-12, "flat spectrum at the node");
        sum_y += atm.grid.xyz_weight[k][1];
    }
    check_rel(sum_y, 106.857, 1e-3, "sum of Y weights = integral of ybar");
    atmosphere_free(&atm);
    char *slope = constituent_file(
        "\n  \"solar_irradiance\": {\"wavelengths_nm\": [380, 780], \"values\": [1.0, 2.0]},", grey);
    load(&atm, slope, 0.0, 1.0, 0.2);
    for (int k = 1; k < atm.grid.count - 1; k++)
        check_rel(atm.grid.solar_irradiance[k], 1.0 + (atm.grid.lambda_nm[k] - 380.0) / 400.0, 1e-12,
                  "linear spectrum at the node");
    atmosphere_free(&atm);
    unlink(flat);
    unlink(slope);
    free(flat);
    free(slope);
}

typedef struct bad_case {
    const char *what;
    const char *text;     /* the whole file */
    double lambda_nm;     /* grid: one wavelength, or 0 for colour */
    const char *expected; /* in the message, after "FILE" */
} bad_case;

#define GOOD_MOL                                                                                                  \
    "{\"name\": \"molecules\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"scattering\": " \
    "{\"wavelengths_nm\": [440, 550, 680], \"values\": [33.1e-6, 13.5e-6, 5.8e-6]}, \"phase\": {\"type\": "        \
    "\"rayleigh\"}}"
#define FILE_WITH(c) "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"constituents\": [" c "]}"

static void malformed_files_are_refused(void **state)
{
    const bad_case cases[] = {
        {"syntax error", "{\n  \"planet_radius_km\": 6360,\n  \"top_altitude_km\": 60,,\n}\n", 550,
         ":3:25: JSON syntax error at byte 54: a comma before '}'"},
        {"trailing comma in an array", "{\"constituents\": [1, 2, ]}", 550,
         ":1:23: JSON syntax error at byte 22: a comma before ']'"},
        {"raw control byte", "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"constituents\": [{\"name\": \"m\x01\"}]}",
         550, ":1:79: JSON syntax error at byte 78: raw control byte 0x01 in a string (escape it)"},
        {"invalid UTF-8", "{\"constituents\": [{\"name\": \"\xc3\x28\"}]}", 550,
         ":1:29: JSON syntax error at byte 28: invalid UTF-8 (byte 0xc3)"},
        {"UTF-16 surrogate in UTF-8", "{\"constituents\": [{\"name\": \"\xed\xa0\x80\"}]}", 550,
         ":1:29: JSON syntax error at byte 28: invalid UTF-8 (byte 0xed)"},
        {"leading zero", "{\"planet_radius_km\": 06360}", 550,
         ":1:22: JSON syntax error at byte 21: a number with a leading zero"},
        {"negative leading zero", "{\"planet_radius_km\": -00.5}", 550,
         ":1:23: JSON syntax error at byte 22: a number with a leading zero"},
        {"missing comma", "{\n  \"planet_radius_km\": 6360\n  \"top_altitude_km\": 60\n}\n", 550,
         ":3:3: JSON syntax error at '\"top_altitud'"},
        {"truncated", "{\n  \"planet_radius_km\": 6360,\n  \"constituents\": [\n", 550,
         ":4:1: JSON syntax error: unexpected end of file"},
        {"not an object", "[1, 2]", 550, ": $: must be an object, not an array"},
        {"unknown top-level key", "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"albedo\": 0.3, "
                                  "\"constituents\": [" GOOD_MOL "]}",
         550, ": $: unknown key \"albedo\""},
        {"unknown constituent key",
         FILE_WITH("{\"name\": \"m\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                   "\"scattering\": 1e-5, \"phsae\": {\"type\": \"rayleigh\"}}"),
         550, ": $.constituents[0]: unknown key \"phsae\""},
        {"duplicate key", "{\"planet_radius_km\": 6360, \"planet_radius_km\": 6000, \"top_altitude_km\": 60, "
                          "\"constituents\": [" GOOD_MOL "]}",
         550, ": $: key \"planet_radius_km\" appears twice"},
        {"wrong type", "{\"planet_radius_km\": \"6360\", \"top_altitude_km\": 60, \"constituents\": [" GOOD_MOL "]}",
         550, ": $.planet_radius_km: must be a number, not a string"},
        {"missing top", "{\"planet_radius_km\": 6360, \"constituents\": [" GOOD_MOL "]}", 550,
         ": $: missing \"top_altitude_km\""},
        {"g out of range",
         FILE_WITH(GOOD_MOL ", {\"name\": \"a\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 1.2}, "
                            "\"extinction\": 4e-6, \"single_scattering_albedo\": 0.9, "
                            "\"phase\": {\"type\": \"henyey-greenstein\", \"g\": 1.2}}"),
         550, ": $.constituents[1].phase.g: must be in [-0.99999, 0.99999], not 1.2"},
        /* nearer 1 the Henyey-Greenstein peak overflowed and the map was NaN (exit 0) */
        {"g too near 1",
         FILE_WITH(GOOD_MOL ", {\"name\": \"a\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 1.2}, "
                            "\"extinction\": 4e-6, \"single_scattering_albedo\": 0.9, "
                            "\"phase\": {\"type\": \"henyey-greenstein\", \"g\": 0.99999999}}"),
         550, ": $.constituents[1].phase.g: must be in [-0.99999, 0.99999], not 0.99999999"},
        /* a larger sun overflowed the disk's radiance in 32-bit floats (inf in the map, exit 0) */
        {"solar irradiance too large",
         "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"solar_irradiance\": 1e300, \"constituents\": ["
         GOOD_MOL "]}",
         550, ": $.solar_irradiance: must be in [0, 1e+06], not 1e+300"},
        {"albedo out of range",
         "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"ground_albedo\": 1.5, \"constituents\": [" GOOD_MOL
         "]}",
         550, ": $.ground_albedo: must be in [0, 1], not 1.5"},
        {"negative coefficient",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"absorption\": "
                   "{\"wavelengths_nm\": [400, 700], \"values\": [1e-6, -1e-6]}}"),
         550, ": $.constituents[0].absorption.values[1]: must be in [0, 1], not -1e-06"},
        {"wavelengths not ascending",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"absorption\": "
                   "{\"wavelengths_nm\": [400, 400], \"values\": [1e-6, 1e-6]}}"),
         550, ": $.constituents[0].absorption.wavelengths_nm[1]: must be greater than the value before it (400), "
              "not 400"},
        {"wavelength coverage (one wavelength)", FILE_WITH(GOOD_MOL), 380,
         ": $.constituents[0].scattering: given for 440-680 nm (constituent \"molecules\"), but the render needs "
         "380 nm"},
        {"wavelength coverage (colour)", FILE_WITH(GOOD_MOL), 0,
         ": $.constituents[0].scattering: given for 440-680 nm (constituent \"molecules\"), but the render needs "
         "380-780 nm"},
        {"scatterer without phase",
         FILE_WITH("{\"name\": \"m\", \"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                   "\"scattering\": 1e-5}"),
         550, ": $.constituents[0]: missing \"phase\": the constituent scatters"},
        {"profile not covering the top",
         FILE_WITH("{\"profile\": {\"type\": \"tabulated\", \"altitudes_km\": [0, 10, 40], \"values\": [0, 1, 0]}, "
                   "\"absorption\": 1e-6}"),
         550, ": $.constituents[0].profile.altitudes_km: must cover the atmosphere from 0 to 60 km, covers 0 to 40 km"},
        {"unknown profile type",
         FILE_WITH("{\"profile\": {\"type\": \"linear\"}, \"absorption\": 1e-6}"), 550,
         ": $.constituents[0].profile.type: \"linear\" is not a profile type"},
        {"key of another phase type",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"scattering\": 1e-5, "
                   "\"phase\": {\"type\": \"rayleigh\", \"g\": 0.5}}"),
         550, ": $.constituents[0].phase: \"g\" does not apply to a Rayleigh phase function"},
        {"depolarisation out of range",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"scattering\": 1e-5, "
                   "\"phase\": {\"type\": \"rayleigh\", \"depolarization\": 0.9}}"),
         550, ": $.constituents[0].phase.depolarization: must be in [0, 0.857143], not 0.9"},
        {"extinction without albedo",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"extinction\": 1e-5}"), 550,
         ": $.constituents[0]: \"extinction\" needs \"single_scattering_albedo\""},
        {"no constituents", "{\"planet_radius_km\": 6360, \"top_altitude_km\": 60, \"constituents\": []}", 550,
         ": $.constituents: must hold 1 to 12 constituents, holds 0"},
        {"tabulated phase rows",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"scattering\": 1e-5, "
                   "\"phase\": {\"type\": \"tabulated\", \"angles_deg\": [0, 90, 180], \"values\": [1, 1]}}"),
         550, ": $.constituents[0].phase.values: has 2 values for 3 angles"},
        {"tabulated phase angles",
         FILE_WITH("{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, \"scattering\": 1e-5, "
                   "\"phase\": {\"type\": \"tabulated\", \"angles_deg\": [0, 90, 170], \"values\": [1, 1, 1]}}"),
         550, ": $.constituents[0].phase.angles_deg: must run from 0 to 180 degrees, runs from 0 to 170"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *path = test_write_temp("atmosphere", cases[i].text);
        spectral_grid grid;
        if (cases[i].lambda_nm > 0.0)
            spectral_grid_single(&grid, cases[i].lambda_nm);
        else
            spectral_grid_visible(&grid);
        atmosphere atm;
        fm_error err = {0};
        fm_status s = atmosphere_init_from_file(&atm, path, &grid, 1.0, 0.2, &err);
        test_check_input_error(cases[i].what, s, &err, "atmosphere_file", path, cases[i].expected);
        unlink(path);
        free(path);
    }
    /* a file that does not exist */
    spectral_grid grid;
    spectral_grid_single(&grid, 550.0);
    atmosphere atm;
    fm_error err = {0};
    assert_int_equal(atmosphere_init_from_file(&atm, "/nonexistent/atm.json", &grid, 1.0, 0.2, &err),
                     FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "/nonexistent/atm.json: cannot open"));
}

/* Through the public API: the observer must be inside the file's atmosphere. */
static void observer_inside_the_file_atmosphere(void **state)
{
    char *path = test_write_temp(
        "atmosphere", "{\"planet_radius_km\": 3390, \"top_altitude_km\": 10, \"constituents\": [{\"profile\": "
                      "{\"type\": \"exponential\", \"scale_height_km\": 11}, \"scattering\": 1e-6, "
                      "\"phase\": {\"type\": \"henyey-greenstein\", \"g\": 0.6}}]}");
    fm_sky_params p = test_params(30.0, 550.0);
    p.atmosphere_file = path;
    p.observer_altitude_m = 15000.0;
    fm_sky *sky = NULL;
    fm_error err;
    assert_int_equal(fm_sky_create(&p, &sky, &err), FM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.parameter, "observer_altitude_m");
    p.observer_altitude_m = 2000.0;
    sky = test_sky(&p);
    check_abs(sky->observer.z, 3392e3, 1e-6, "observer above the file's planet");
    fm_sky_destroy(sky);
    unlink(path);
    free(path);
}

/* An atmosphere that absorbs and scatters nothing (a vacuum planet, or absorption alone): the sky
 * is black and the ground is lit by the direct sun only, L = albedo / pi x the sun's horizontal
 * irradiance.  (Its table paths once drew a direction from a vertex without a phase function, and
 * the maps were NaN, exit 0.) */
static void non_scattering_atmosphere_renders_a_black_sky(void **state)
{
    const char *constituents[] = {"{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                                  "\"absorption\": 1e-5}",
                                  "{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                                  "\"scattering\": 0, \"phase\": {\"type\": \"rayleigh\"}}"};
    for (int f = 0; f < 2; f++) {
        char *path = constituent_file("\n  \"ground_albedo\": 0.3,\n  \"solar_irradiance\": 1,", constituents[f]);
        fm_sky_params p = test_params(30.0, 550.0);
        p.atmosphere_file = path;
        fm_sky *sky = test_sky(&p);
        fm_sun_light sun;
        fm_sky_sun_light(sky, &sun);
        const double ground = 0.3 / FM_PI * sun.horizontal_irradiance[0];
        for (int q = 0; q < 2; q++) {
            fm_image *img = test_render(sky, 64, q ? FM_QUALITY_FINAL : FM_QUALITY_PREVIEW, 0, 1, 0, 1.0, 0);
            double sky_max = 0.0;
            for (int y = 0; y < img->height; y++)
                for (int x = 0; x < img->width; x++) {
                    double v = img->pixels[(size_t)y * img->width + x];
                    assert_true(isfinite(v));
                    if (y < img->height / 2)
                        sky_max = fmax(sky_max, v);
                    else
                        check_rel(v, ground, 1e-3, "ground lit by the sun alone");
                }
            print_message("file %d, quality %d: sky up to %.1e, ground %.5f (sun alone %.5f)\n", f, q, sky_max,
                          img->pixels[(size_t)(img->height - 1) * img->width], ground);
            assert_true(sky_max < 1e-20);
            fm_image_destroy(img);
        }
        fm_sky_destroy(sky);
        unlink(path);
        free(path);
    }
    /* scattering at the red end only: a colour map's first vertices whose hero wavelength scatters
     * nothing drew no direction (NaN in 768 of a 32 x 16 map's 2048 values) */
    char *path = constituent_file("", "{\"profile\": {\"type\": \"exponential\", \"scale_height_km\": 8}, "
                                      "\"scattering\": {\"wavelengths_nm\": [380, 550, 551, 780], "
                                      "\"values\": [0, 0, 1e-5, 1e-5]}, \"phase\": {\"type\": \"rayleigh\"}}");
    fm_sky_params p = test_params(30.0, 0.0);
    p.atmosphere_file = path;
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 32, FM_QUALITY_FINAL, 0, 1, 0, 1.0, 0);
    size_t n = (size_t)img->width * img->height * img->channels, finite = 0;
    for (size_t i = 0; i < n; i++)
        finite += isfinite(img->pixels[i]) != 0;
    assert_int_equal(finite, n);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
    unlink(path);
    free(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reference_atmospheres_build_their_coefficients),
        cmocka_unit_test(reference_rayleigh_optical_depth),
        cmocka_unit_test(majorant_shells_follow_the_top),
        cmocka_unit_test(molecular_fixture_matches_builtin_coefficients),
        cmocka_unit_test(file_solar_spectrum_on_the_colour_grid),
        cmocka_unit_test(tabulated_phase_from_a_file),
        cmocka_unit_test(malformed_files_are_refused),
        cmocka_unit_test(observer_inside_the_file_atmosphere),
        cmocka_unit_test(non_scattering_atmosphere_renders_a_black_sky),
        cmocka_unit_test(molecular_fixture_renders_the_builtin_sky),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
