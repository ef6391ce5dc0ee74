/* Aerosol biomes: optical depths against OPAC, spectral and absorption character, turbidity,
 * the tabulated Mie phase functions in the atmosphere (normalisation, sampling); biome files:
 * defaults, and malformed ones refused with the file, the JSON path and the problem. */
#include "check.h"

#include "aerosol/aerosol.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase.h"
#include "presets.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* OPAC extinction at 550 nm per particle per cm^3 (km^-1), from the OPAC optdat files (Hess,
 * Koepke & Schult 1998): an independent source, not our Mie tables. */
static const struct {
    const char *code;
    int rh;
    double ext_km;
} opac550[] = {
    {"waso", 0, 3.905e-6},  {"waso", 50, 6.366e-6}, {"waso", 80, 9.584e-6}, {"inso", 0, 8.496e-3},
    {"soot", 0, 5.540e-7},  {"suso", 0, 7.120e-5},  {"suso", 80, 2.629e-4}, {"suso", 50, 1.654e-4},
    {"mitr", 0, 5.853e-3},
    {"ssam", 80, 3.743e-3}, {"sscm", 80, 2.185e-1}, {"minm", 0, 7.140e-5},  {"miam", 0, 3.121e-3},
    {"micm", 0, 7.798e-2},  {"ssam", 50, 2.513e-3}, {"sscm", 50, 1.439e-1},
};

static double opac_ext_m2(const char *code, double rh)
{
    int hygroscopic = !strcmp(code, "waso") || !strcmp(code, "ssam") || !strcmp(code, "sscm") || !strcmp(code, "suso");
    for (size_t i = 0; i < sizeof opac550 / sizeof opac550[0]; i++)
        if (!strcmp(opac550[i].code, code) && opac550[i].rh == (hygroscopic ? (int)rh : 0))
            return opac550[i].ext_km * 1e-5 * 1e-4; /* km^-1 per cm^-3 -> cm^2 -> m^2 */
    fail_msg("no OPAC value for %s at %g %%", code, rh);
    return 0.0;
}

static biome load(const char *name)
{
    biome b;
    fm_error err;
    if (biome_load(name, NULL, &b, &err))
        fail_msg("%s", err.message);
    return b;
}

/* The AOD the biome definition implies with OPAC's own cross sections, layer by layer. */
static double opac_aod550(const biome *b, double rh, double *boundary_layer)
{
    double tau = 0.0;
    for (int i = 0; i < b->layer_count; i++) {
        const biome_layer *l = &b->layer[i];
        double h = l->humidity_percent >= 0 ? l->humidity_percent : rh, beta = 0.0;
        for (int c = 0; c < l->component_count; c++)
            beta += l->component[c].density_m3 * opac_ext_m2(l->component[c].code, h);
        double d = l->top_m - l->bottom_m;
        double column = l->scale_height_m > 0 ? l->scale_height_m * (1 - exp(-d / l->scale_height_m)) : d;
        tau += beta * column;
        if (i == 0 && boundary_layer)
            *boundary_layer = beta * column;
    }
    return tau;
}

static double aod550(const biome *b, double rh)
{
    aerosol_column c;
    fm_error err;
    if (aerosol_biome_column(b, rh, 550.0, &c, &err))
        fail_msg("%s", err.message);
    return c.tau_ext;
}

/* PHYSICS.md 5.3: boundary-layer AOD(550) of the OPAC mixtures at 80 % humidity, computed from the
 * optdat files; each biome adds its free troposphere and stratosphere. */
static void aod_matches_opac(void **state)
{
    static const struct {
        const char *biome;
        double bl_rh80, bl_rh50; /* 0: not tabulated */
    } cases[] = {
        {"remote-continental", 0.046, 0.032}, {"rural", 0.133, 0.093}, {"urban", 0.625, 0.465},
        {"desert-dust", 0.275, 0.263},        {"maritime-clean", 0.078, 0.052}, {"polar-arctic", 0.045, 0.032},
        {"polar-antarctic", 0.066, 0.041},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        biome b = load(cases[i].biome);
        double bl80, bl50;
        double opac80 = opac_aod550(&b, 80, &bl80), opac50 = opac_aod550(&b, 50, &bl50);
        print_message("%s: boundary layer %.4f (table %.3f), free troposphere + stratosphere %.4f\n",
                      cases[i].biome, bl80, cases[i].bl_rh80, opac80 - bl80);
        check_rel(bl80, cases[i].bl_rh80, 0.02, "the biome restates OPAC's boundary layer");
        check_rel(aod550(&b, 80), cases[i].bl_rh80 + (opac80 - bl80), 0.05, "AOD(550) at 80 % vs PHYSICS.md 5.3");
        check_rel(aod550(&b, 50), cases[i].bl_rh50 + (opac50 - bl50), 0.05, "AOD(550) at 50 % vs PHYSICS.md 5.3");
    }
    const char *others[] = {"background", "maritime-mineral"};
    for (int i = 0; i < 2; i++) {
        biome b = load(others[i]);
        double expect = opac_aod550(&b, b.humidity_percent, NULL);
        check_rel(aod550(&b, b.humidity_percent), expect, 0.05, others[i]);
    }
    biome bg = load("background");
    double t = aod550(&bg, bg.humidity_percent);
    assert_true(t > 0.02 && t < 0.05); /* d'Almeida's background aerosol: 0.02-0.05 */
}

static aerosol_column column(const char *name, double lambda_nm)
{
    biome b = load(name);
    aerosol_column c;
    fm_error err;
    if (aerosol_biome_column(&b, b.humidity_percent, lambda_nm, &c, &err))
        fail_msg("%s", err.message);
    return c;
}

static double angstrom(const char *name)
{
    return -log(column(name, 870).tau_ext / column(name, 440).tau_ext) / log(870.0 / 440.0);
}

/* Coarse dust is nearly grey, fine urban aerosol is not; soot makes urban air absorb. */
static void spectral_character(void **state)
{
    double a_desert = angstrom("desert-dust"), a_urban = angstrom("urban");
    aerosol_column u = column("urban", 550);
    print_message("Angstrom exponent: desert-dust %.3f, urban %.3f; urban ssa(550) %.3f\n", a_desert, a_urban,
                  u.tau_sca / u.tau_ext);
    assert_true(a_desert < 0.5);
    assert_true(a_urban > 1.0);
    assert_true(u.tau_sca / u.tau_ext < 0.9);
    aerosol_column m = column("maritime-clean", 550);
    assert_true(m.tau_sca / m.tau_ext > 0.98); /* sea salt barely absorbs */
}

/* Vertical optical depth through the built atmosphere's aerosol species at grid wavelength k. */
static double species_aod(const fm_sky *sky, int k)
{
    double tau = 0.0;
    for (int c = 0; c < sky->atm.species_count; c++)
        if (!strcmp(sky->atm.species[c].name, "aerosol"))
            tau += (sky->atm.species[c].sigma_s[k] + sky->atm.species[c].sigma_a[k]) *
                   profile_column(&sky->atm.species[c].profile);
    return tau;
}

static fm_sky_params aerosol_params(const char *name, double turbidity)
{
    fm_sky_params p = test_params(30, 550);
    p.biome = name;
    p.turbidity = turbidity;
    return p;
}

/* Turbidity multiplies the number density: AOD scales linearly; 0 is no aerosol at all.  The
 * profiles the path tracer sees hold the reported column. */
static void turbidity_scales_linearly(void **state)
{
    fm_sky_params p1 = aerosol_params("rural", 1.0), p3 = aerosol_params("rural", 3.0);
    fm_sky *s1 = test_sky(&p1), *s3 = test_sky(&p3);
    fm_composition c1, c3;
    fm_sky_composition(s1, &c1);
    fm_sky_composition(s3, &c3);
    check_rel(c3.aerosol_tau550, 3.0 * c1.aerosol_tau550, 1e-12, "reported AOD at turbidity 3");
    check_rel(species_aod(s1, 0), c1.aerosol_tau550, 2e-3, "the rendered profiles hold the reported AOD");
    check_rel(species_aod(s3, 0), 3.0 * species_aod(s1, 0), 1e-12, "rendered AOD at turbidity 3");
    fm_sky_destroy(s1);
    fm_sky_destroy(s3);

    fm_sky_params pa = aerosol_params("urban", 1.0);
    pa.aod550 = 0.3;
    fm_sky *sa = test_sky(&pa);
    fm_composition ca;
    fm_sky_composition(sa, &ca);
    check_rel(ca.aerosol_tau550, 0.3, 1e-9, "--aod550 sets the optical depth");
    check_rel(species_aod(sa, 0), 0.3, 2e-3, "the rendered profiles hold it");
    fm_sky_destroy(sa);
}

static void turbidity_zero_is_none(void **state)
{
    fm_sky_params p0 = aerosol_params("urban", 0.0), pn = aerosol_params("none", 1.0);
    p0.wavelength_nm = pn.wavelength_nm = 0.0;
    fm_sky *s0 = test_sky(&p0), *sn = test_sky(&pn);
    assert_int_equal(s0->atm.species_count, sn->atm.species_count);
    fm_image *a = test_render(s0, 32, FM_QUALITY_PREVIEW, 2, 5, 0, 0.25, 1);
    fm_image *b = test_render(sn, 32, FM_QUALITY_PREVIEW, 2, 5, 0, 0.25, 1);
    assert_memory_equal(a->pixels, b->pixels, sizeof(float) * 3 * 32 * 16);
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_sky_destroy(s0);
    fm_sky_destroy(sn);
}

/* The mixture's phase function at every grid wavelength integrates to 1 over the sphere
 * (independent quadrature, fine near the forward peak), and its sampler matches it. */
static void mixture_phase_normalised_and_sampled(void **state)
{
    fm_sky_params p = aerosol_params("desert-dust", 1.0);
    p.wavelength_nm = 0.0;
    fm_sky *sky = test_sky(&p);
    const species *sp = NULL;
    for (int c = 0; c < sky->atm.species_count && !sp; c++)
        if (!strcmp(sky->atm.species[c].name, "aerosol"))
            sp = &sky->atm.species[c];
    assert_non_null(sp);
    for (int k = 0; k < sky->atm.grid.count; k += 10) {
        /* integrate in theta on a grid uniform in sqrt(theta): dense at the forward peak */
        const int n = 200000;
        double s = 0.0;
        for (int i = 0; i < n; i++) {
            double u = (i + 0.5) / n, theta = FM_PI * u * u, dtheta = 2.0 * FM_PI * u / n;
            s += phase_evaluate(&sp->phase, k, cos(theta)) * 2.0 * FM_PI * sin(theta) * dtheta;
        }
        check_abs(s, 1.0, 1e-3, "desert boundary-layer phase function over the sphere");
    }
    /* chi-square of the sampler at 380 nm over bins equal in sqrt(theta) */
    enum { BINS = 60 };
    double counts[BINS] = {0};
    const int N = 1000000;
    rng r = rng_for(3, 1, 4);
    for (int i = 0; i < N; i++) {
        double theta = acos(fmax(-1.0, fmin(1.0, phase_sample(&sp->phase, 0, rng_uniform(&r)))));
        int b = (int)(sqrt(theta / FM_PI) * BINS);
        counts[b < BINS ? b : BINS - 1] += 1;
    }
    double chi2 = 0.0;
    for (int b = 0; b < BINS; b++) {
        double expect = 0.0;
        const int sub = 400;
        for (int i = 0; i < sub; i++) {
            double u = (b + (i + 0.5) / sub) / BINS, theta = FM_PI * u * u;
            expect += phase_evaluate(&sp->phase, 0, cos(theta)) * 2.0 * FM_PI * sin(theta) * 2.0 * FM_PI * u /
                      (BINS * sub);
        }
        expect *= N;
        chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
    }
    print_message("chi-square = %.1f (59 degrees of freedom)\n", chi2);
    assert_true(chi2 < 99.6); /* 99.9 % point */
    fm_sky_destroy(sky);
}

/* --aerosol-phase hg: the same layers, Henyey-Greenstein with each layer's Mie asymmetry
 * parameter, so the mean scattering angle is unchanged while the forward peak is not. */
static void henyey_greenstein_keeps_g(void **state)
{
    fm_sky_params pm = aerosol_params("maritime-clean", 1.0), ph = pm;
    ph.aerosol_phase = FM_AEROSOL_PHASE_HG;
    fm_sky *sm = test_sky(&pm), *sh = test_sky(&ph);
    assert_int_equal(sm->atm.species_count, sh->atm.species_count);
    int layers = 0;
    for (int c = 0; c < sm->atm.species_count; c++) {
        const species *a = &sm->atm.species[c], *b = &sh->atm.species[c];
        if (strcmp(a->name, "aerosol"))
            continue;
        layers++;
        assert_int_equal(a->phase.kind, PHASE_TABULATED);
        assert_int_equal(b->phase.kind, PHASE_HENYEY_GREENSTEIN);
        check_abs(phase_asymmetry(&b->phase, 0), phase_asymmetry(&a->phase, 0), 2e-3, "HG g = Mie g");
        double mie = phase_evaluate(&a->phase, 0, 1.0), hg = phase_evaluate(&b->phase, 0, 1.0);
        print_message("forward (sr^-1): Mie %.1f, HG %.1f\n", mie, hg);
        if (layers == 1) /* the marine boundary layer: sea salt's diffraction peak, which HG misses */
            assert_true(mie > 2.0 * hg);
    }
    assert_true(layers >= 2);
    fm_sky_destroy(sm);
    fm_sky_destroy(sh);
}

/* ---- biome files: schema, defaults and messages --------------------------------------------- */

#define LAYER(extra, densities)                                                                                   \
    "{\"name\": \"bl\", \"bottom_km\": 0, \"top_km\": 2" extra ", \"number_density_cm3\": {" densities "}}"
#define BIOME(layers) "{\"name\": \"x\", \"humidity_percent\": 50, \"layers\": [" layers "]}"

/* Optional numbers keep their defaults: no scale height (constant), the ambient humidity (-1). */
static void biome_file_defaults(void **state)
{
    (void)state;
    const char *text = BIOME(LAYER("", "\"waso\": 10, \"soot\": 0.5") ", {\"name\": \"top\", \"bottom_km\": 2, "
                                "\"top_km\": 8, \"scale_height_km\": 1.5, \"humidity_percent\": 20, "
                                "\"number_density_cm3\": {\"suso\": 3}}");
    char *path = test_write_temp("biome", text);
    biome b;
    fm_error err = {0};
    if (biome_load(path, "/nonexistent", &b, &err))
        fail_msg("%s", err.message);
    assert_string_equal(b.name, "x");
    assert_int_equal(b.layer_count, 2);
    check_abs(b.humidity_percent, 50.0, 0.0, "ambient humidity");
    check_abs(b.layer[0].scale_height_m, 0.0, 0.0, "no scale height: constant density");
    check_abs(b.layer[0].humidity_percent, -1.0, 0.0, "no layer humidity: the ambient one");
    check_abs(b.layer[0].top_m, 2000.0, 0.0, "top in m");
    assert_int_equal(b.layer[0].component_count, 2);
    assert_string_equal(b.layer[0].component[1].code, "soot");
    check_abs(b.layer[0].component[1].density_m3, 0.5e6, 0.0, "per cm^3 to per m^3");
    check_abs(b.layer[1].scale_height_m, 1500.0, 0.0, "scale height in m");
    check_abs(b.layer[1].humidity_percent, 20.0, 0.0, "layer humidity");
    unlink(path);
    free(path);
}

static void malformed_biome_files_are_refused(void **state)
{
    (void)state;
    const struct {
        const char *what, *text, *expected; /* expected: in the message, after "biome: FILE" */
    } cases[] = {
        {"truncated", "{\"name\": \"x\", \"humidity_percent\": 50, \"layers\": [\n  {\"name\": \"bl\",\n",
         ":3:1: JSON syntax error: unexpected end of file"},
        {"not an object", "[]", ": $: must be an object, not an array"},
        {"unknown key", "{\"name\": \"x\", \"humidity\": 50, \"layers\": []}", ": $: unknown key \"humidity\""},
        {"missing name", "{\"humidity_percent\": 50, \"layers\": [" LAYER("", "\"waso\": 1") "]}",
         ": $: missing \"name\""},
        {"missing humidity", "{\"name\": \"x\", \"layers\": [" LAYER("", "\"waso\": 1") "]}",
         ": $: missing \"humidity_percent\""},
        {"no layers", BIOME(""), ": $.layers: must hold 1 to 6 layers, holds 0"},
        {"layer key typo", BIOME(LAYER(", \"scale_height\": 2", "\"waso\": 1")),
         ": $.layers[0]: unknown key \"scale_height\""},
        {"layer humidity out of range", BIOME(LAYER(", \"humidity_percent\": 100", "\"waso\": 1")),
         ": $.layers[0].humidity_percent: must be in [0, 99], not 100"},
        {"scale height out of range", BIOME(LAYER(", \"scale_height_km\": 0.01", "\"waso\": 1")),
         ": $.layers[0].scale_height_km: must be in [0.1, 1000], not 0.01"},
        {"upside down",
         BIOME("{\"name\": \"bl\", \"bottom_km\": 3, \"top_km\": 2, \"number_density_cm3\": {\"waso\": 1}}"),
         ": $.layers[0].top_km: must be above bottom_km (3), not 2"},
        {"overlap", BIOME(LAYER("", "\"waso\": 1") ", " LAYER("", "\"suso\": 1")),
         ": $.layers[1].bottom_km: overlaps the layer below"},
        {"unknown component", BIOME(LAYER("", "\"wasso\": 10")),
         ": $.layers[0].number_density_cm3: unknown OPAC component \"wasso\""},
        {"repeated component", BIOME(LAYER("", "\"waso\": 10, \"waso\": 20")),
         ": $.layers[0].number_density_cm3: key \"waso\" appears twice"},
        {"density not a number", BIOME(LAYER("", "\"waso\": \"10\"")),
         ": $.layers[0].number_density_cm3.waso: must be a number, not a string"},
        {"negative density", BIOME(LAYER("", "\"waso\": -1")),
         ": $.layers[0].number_density_cm3.waso: must be in [0, 1e+07], not -1"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *path = test_write_temp("biome", cases[i].text);
        biome b;
        fm_error err = {0};
        fm_status s = biome_load(path, "/nonexistent", &b, &err);
        test_check_input_error(cases[i].what, s, &err, "biome", path, cases[i].expected);
        unlink(path);
        free(path);
    }
    /* a file that does not exist is bad input too */
    biome b;
    fm_error err = {0};
    assert_int_equal(biome_load("/nonexistent/biome.json", "/nonexistent", &b, &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "biome: /nonexistent/biome.json: cannot open"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(aod_matches_opac),
        cmocka_unit_test(spectral_character),
        cmocka_unit_test(turbidity_scales_linearly),
        cmocka_unit_test(turbidity_zero_is_none),
        cmocka_unit_test(mixture_phase_normalised_and_sampled),
        cmocka_unit_test(henyey_greenstein_keeps_g),
        cmocka_unit_test(biome_file_defaults),
        cmocka_unit_test(malformed_biome_files_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
