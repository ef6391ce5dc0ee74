/* The generated OPAC component table (core/src/data/aerosol_optics_opac.c): regenerating it with
 * tools/aerosol_tables.c gives the stored numbers (spot check: one wavelength of every component,
 * the generator's --spot-check, since the whole table takes minutes; scripts/make-aerosol-tables
 * regenerates all of it), and every stored phase function integrates to 1
 * and has the stored asymmetry parameter as its mean cosine, as a consumer interpolating it
 * linearly in cos(theta) sees it. */
#define _POSIX_C_SOURCE 200809L /* mkstemp, close */

#include "check.h"

#include "aerosol/aerosol_optics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void stored_phase_functions_consistent(void **state)
{
    assert_int_equal(aerosol_optics_count, 38);
    double worst_norm = 0.0, worst_g = 0.0;
    for (int e = 0; e < aerosol_optics_count; e++) {
        const aerosol_optics *t = &aerosol_optics_table[e];
        assert_ptr_equal(aerosol_optics_find(t->component, t->humidity_percent), t);
        for (int i = 0; i < AEROSOL_WAVELENGTH_COUNT; i++) {
            assert_true(t->ext_m2[i] > 0.0 && t->sca_m2[i] > 0.0 && t->sca_m2[i] <= t->ext_m2[i] * (1.0 + 1e-6));
            double mean_cos, norm = aerosol_phase_integral(t->phase[i], &mean_cos);
            char what[96];
            snprintf(what, sizeof what, "%s%02d %.0f nm phase integral", t->component, t->humidity_percent,
                     aerosol_optics_wavelength_nm(i));
            check_abs(norm, 1.0, 1e-3, what);
            snprintf(what, sizeof what, "%s%02d %.0f nm phase mean cosine vs g", t->component, t->humidity_percent,
                     aerosol_optics_wavelength_nm(i));
            check_abs(mean_cos, t->g[i], 2e-3, what);
            worst_norm = fmax(worst_norm, fabs(norm - 1.0));
            worst_g = fmax(worst_g, fabs(mean_cos - t->g[i]));
        }
    }
    print_message("worst |integral - 1| = %.2e, worst |<cos> - g| = %.2e\n", worst_norm, worst_g);
    assert_null(aerosol_optics_find("waso", 60));
    assert_null(aerosol_optics_find("soot", 80));
    assert_non_null(aerosol_optics_find("sscm", 99));
    check_abs(aerosol_optics_angle_rad(AEROSOL_ANGLE_COUNT - 1), 3.14159265358979323846, 1e-15, "last angle");
}

#ifndef FM_SKIP_REGENERATION
/* All numbers of the table's initialiser, in order (comments skipped). */
static double *table_numbers(const char *path, size_t *count)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return NULL;
    size_t cap = 1 << 20, n = 0;
    double *v = malloc(cap * sizeof *v);
    char line[4096];
    int in_table = 0;
    while (v && fgets(line, sizeof line, f)) {
        if (!in_table) {
            in_table = strstr(line, "aerosol_optics_table[] = {") != NULL;
            continue;
        }
        char *c = strstr(line, "/*");
        if (c)
            *c = '\0';
        for (char *p = line; *p;) {
            if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '.') {
                char *end;
                double x = strtod(p, &end);
                if (end == p) {
                    p++;
                    continue;
                }
                if (n == cap) {
                    cap *= 2;
                    double *nv = realloc(v, cap * sizeof *v);
                    if (!nv) {
                        free(v);
                        v = NULL;
                        break;
                    }
                    v = nv;
                }
                v[n++] = x;
                p = end;
            } else if (*p == '"') { /* skip the component code */
                char *q = strchr(p + 1, '"');
                p = q ? q + 1 : p + 1;
            } else {
                p++;
            }
        }
    }
    fclose(f);
    *count = n;
    return v;
}
#endif

static void regenerates_stored_table(void **state)
{
#ifdef FM_SKIP_REGENERATION
    print_message("regeneration skipped in the sanitizer build (the generator runs for minutes there)\n");
    skip();
#else
    char out[] = "/tmp/fm_aerosol_optics_XXXXXX";
    int fd = mkstemp(out);
    assert_true(fd >= 0);
    close(fd);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' '%s' 2 --spot-check", FM_AEROSOL_GENERATOR, out);
    assert_int_equal(system(cmd), 0);
    size_t n_new, n_old;
    double *fresh = table_numbers(out, &n_new), *stored = table_numbers(FM_AEROSOL_STORED_TABLE, &n_old);
    remove(out);
    assert_non_null(fresh);
    assert_non_null(stored);
    assert_int_equal(n_new, n_old);
    size_t bad = 0, compared = 0;
    double worst = 0.0;
    /* per component: its humidity, then ext, sca and g at W wavelengths, then W phase functions */
    const size_t W = AEROSOL_WAVELENGTH_COUNT, A = AEROSOL_ANGLE_COUNT, per = 1 + 3 * W + W * A;
    assert_int_equal(n_new, n_old);
    assert_int_equal(n_new, per * (size_t)aerosol_optics_count + 1); /* + the closing count */
    for (size_t i = 0; i + 1 < n_new; i++) {
        size_t e = i / per, j = i % per, spot = (size_t)AEROSOL_SPOT_WAVELENGTH((int)e);
        int regenerated = j == 0 || (j <= 3 * W && (j - 1) % W == spot) ||
                          (j > 3 * W && (j - 1 - 3 * W) / A == spot);
        if (!regenerated)
            continue;
        compared++;
        double scale = fmax(fabs(fresh[i]), fabs(stored[i]));
        double d = fabs(fresh[i] - stored[i]);
        if (scale > 0.0)
            worst = fmax(worst, d / scale);
        /* 1e-5 relative, plus one unit in the sixth printed digit */
        if (d > 1.5e-5 * scale)
            bad++;
    }
    print_message("%zu numbers regenerated, worst relative difference %.2e, %zu beyond tolerance\n", compared, worst,
                  bad);
    assert_int_equal(compared, (size_t)aerosol_optics_count * (1 + 3 + A));
    assert_int_equal(bad, 0);
    free(fresh);
    free(stored);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stored_phase_functions_consistent),
        cmocka_unit_test(regenerates_stored_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
