/* The cache of cloud optics (aerosol/cloud_optics.h): the first build computes and writes the file,
 * the second is served from it and is bit-identical to a computation without a cache (the tables
 * and the whole sky's cloud species); a file that is corrupt, truncated, of another key (stale: the
 * optics of another grid under this name) or not a cache file at all is recomputed and replaced,
 * never used; a folder that cannot be written costs only the computation. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "check.h"

#include "aerosol/cloud_optics.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h> /* truncate */

static char dir[64];

/* Three wavelengths: the Mie integrals of a full colour grid take seconds. */
static spectral_grid small_grid(void)
{
    spectral_grid g;
    spectral_grid_visible(&g);
    g.count = 3;
    g.lambda_nm[0] = 420.0;
    g.lambda_nm[1] = 550.0;
    g.lambda_nm[2] = 680.0;
    return g;
}

static cloud_optics_source get(const spectral_grid *grid, const char *cache, cloud_water_table *tb)
{
    cloud_optics_source from;
    fm_error err;
    assert_int_equal(cloud_water_table_get(cloud_type_find("stratus"), grid, 1, cache, tb, &from, &err), FM_OK);
    return from;
}

static void assert_same(const cloud_water_table *a, const cloud_water_table *b)
{
    size_t K = (size_t)a->count;
    assert_int_equal(a->count, b->count);
    assert_memory_equal(a->ext_rel, b->ext_rel, sizeof(double) * K);
    assert_memory_equal(a->ssa, b->ssa, sizeof(double) * K);
    assert_memory_equal(a->phase, b->phase, sizeof(double) * K * CLOUD_ANGLE_COUNT);
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

static void damage(const char *path, long at, const char *bytes, size_t n)
{
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    fseek(f, at, SEEK_SET);
    fwrite(bytes, 1, n, f);
    fclose(f);
}

static void second_build_is_served_from_the_cache(void **state)
{
    (void)state;
    spectral_grid grid = small_grid();
    char path[4096];
    assert_int_equal(cloud_water_table_path(cloud_type_find("stratus"), &grid, dir, path, sizeof path), 0);
    cloud_water_table fresh, first, second;
    assert_int_equal(get(&grid, NULL, &fresh), CLOUD_OPTICS_COMPUTED);
    assert_int_equal(file_size(path), -1); /* no folder, no file */
    assert_int_equal(get(&grid, dir, &first), CLOUD_OPTICS_COMPUTED);
    assert_true(file_size(path) > (long)(sizeof(double) * 3 * CLOUD_ANGLE_COUNT));
    assert_int_equal(get(&grid, dir, &second), CLOUD_OPTICS_FROM_CACHE);
    assert_same(&fresh, &first);
    assert_same(&fresh, &second);
    cloud_water_table_free(&fresh);
    cloud_water_table_free(&first);
    cloud_water_table_free(&second);
}

/* Each damage is refused, the table recomputed (bit-identical) and the file replaced by a good one. */
static void damaged_files_are_rebuilt(void **state)
{
    (void)state;
    spectral_grid grid = small_grid(), other = small_grid();
    other.lambda_nm[2] = 700.0;
    char path[4096], other_path[4096];
    assert_int_equal(cloud_water_table_path(cloud_type_find("stratus"), &grid, dir, path, sizeof path), 0);
    assert_int_equal(cloud_water_table_path(cloud_type_find("stratus"), &other, dir, other_path, sizeof other_path), 0);
    assert_string_not_equal(path, other_path);
    cloud_water_table fresh, tb;
    assert_int_equal(get(&grid, NULL, &fresh), CLOUD_OPTICS_COMPUTED);
    get(&grid, dir, &tb);
    cloud_water_table_free(&tb);
    long size = file_size(path);
    for (int c = 0; c < 5; c++) {
        const char *what[] = {"a flipped byte in the tables", "a flipped byte in the key", "truncated",
                              "another grid's file", "not a cache file"};
        print_message("%s\n", what[c]);
        if (c == 0)
            damage(path, size - 1000, "\x5a", 1);
        else if (c == 1)
            damage(path, 20, "0", 1);
        else if (c == 2)
            assert_int_equal(truncate(path, size / 2), 0);
        else if (c == 3) {
            get(&other, dir, &tb);
            cloud_water_table_free(&tb);
            assert_int_equal(rename(other_path, path), 0);
        } else {
            FILE *f = fopen(path, "wb");
            fputs("{\"not\": \"optics\"}\n", f);
            fclose(f);
        }
        assert_int_equal(get(&grid, dir, &tb), CLOUD_OPTICS_COMPUTED);
        assert_same(&fresh, &tb);
        cloud_water_table_free(&tb);
        assert_int_equal(file_size(path), size);
        assert_int_equal(get(&grid, dir, &tb), CLOUD_OPTICS_FROM_CACHE);
        cloud_water_table_free(&tb);
    }
    cloud_water_table_free(&fresh);
}

static void an_unwritable_folder_only_costs_time(void **state)
{
    (void)state;
    char blocked[128];
    snprintf(blocked, sizeof blocked, "%s/a-file", dir);
    FILE *f = fopen(blocked, "wb");
    fclose(f);
    char below[160];
    snprintf(below, sizeof below, "%s/cache", blocked); /* a folder under a file: never made */
    spectral_grid grid = small_grid();
    cloud_water_table fresh, tb;
    get(&grid, NULL, &fresh);
    assert_int_equal(get(&grid, below, &tb), CLOUD_OPTICS_COMPUTED);
    assert_same(&fresh, &tb);
    cloud_water_table_free(&tb);
    assert_int_equal(get(&grid, below, &tb), CLOUD_OPTICS_COMPUTED);
    cloud_water_table_free(&tb);
    cloud_water_table_free(&fresh);
}

/* The whole sky: its cloud species from the cache equal those computed without one. */
static void sky_built_from_the_cache_is_identical(void **state)
{
    (void)state;
    char nested[128];
    snprintf(nested, sizeof nested, "%s/sky/firmament", dir); /* made with its parents */
    fm_sky_params p = test_params(30.0, 550.0);
    p.clouds = "fog";
    fm_sky *plain = test_sky(&p);
    p.cache_dir = nested;
    fm_sky *first = test_sky(&p), *second = test_sky(&p);
    const atmosphere *a = &plain->atm, *b = &second->atm;
    const species *sa = &a->species[a->species_count - 1], *sb = &b->species[b->species_count - 1];
    assert_memory_equal(sa->sigma_s, sb->sigma_s, sizeof sa->sigma_s);
    assert_memory_equal(sa->sigma_a, sb->sigma_a, sizeof sa->sigma_a);
    for (double mu = -1.0; mu <= 1.0; mu += 1.0 / 64)
        assert_true(phase_evaluate(&sa->phase, 0, mu) == phase_evaluate(&sb->phase, 0, mu));
    assert_true(phase_evaluate(&sa->phase, 0, 1.0) == phase_evaluate(&sb->phase, 0, 1.0));
    fm_sky_destroy(plain);
    fm_sky_destroy(first);
    fm_sky_destroy(second);
}

static int make_dir(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "%s/fm-cloud-cache-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    return mkdtemp(dir) ? 0 : -1;
}

static int remove_dir(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(second_build_is_served_from_the_cache),
        cmocka_unit_test(damaged_files_are_rebuilt),
        cmocka_unit_test(an_unwritable_folder_only_costs_time),
        cmocka_unit_test(sky_built_from_the_cache_is_identical),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
