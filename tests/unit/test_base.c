/* Base utilities: Gauss-Legendre exactness, random-number streams, the Sobol points and their
 * scramble, the parallel loop, the spectral arrays' exp and expm1, new unique files, and the stale
 * temporaries that a sealed file's write removes. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include "base/exp_array.h"
#include "base/platform.h"
#include "base/quadrature.h"
#include "base/rng.h"
#include "base/sealed_file.h"
#include "base/sobol.h"
#include "base/threads.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>
#include <time.h>
#include <utime.h>

static void gauss_legendre_is_exact_for_polynomials(void **state)
{
    for (int n = 1; n <= 16; n++) {
        const gauss_rule *g = gauss_legendre_cached(n);
        for (int degree = 0; degree <= 2 * n - 1; degree++) {
            double sum = 0.0;
            for (int i = 0; i < g->n; i++)
                sum += g->w[i] * pow(g->x[i], degree);
            double exact = degree % 2 ? 0.0 : 2.0 / (degree + 1);
            if (fabs(sum - exact) > 1e-13)
                fail_msg("n=%d degree=%d: %.17g vs %.17g", n, degree, sum, exact);
        }
    }
}

static void rng_streams_are_deterministic_and_uniform(void **state)
{
    rng a = rng_for(42, 7, 3), b = rng_for(42, 7, 3), c = rng_for(42, 7, 4);
    int same = 1, differ = 0;
    for (int i = 0; i < 100; i++) {
        uint32_t x = rng_next_u32(&a), y = rng_next_u32(&b), z = rng_next_u32(&c);
        same &= x == y;
        differ += x != z;
    }
    assert_true(same);
    assert_true(differ > 95);
    /* mean and variance of U[0,1): 1/2 and 1/12 */
    rng r = rng_for(1, 2, 3);
    const int n = 1000000;
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; i++) {
        double u = rng_uniform(&r);
        assert_true(u >= 0.0 && u < 1.0);
        s += u;
        s2 += u * u;
    }
    check_abs(s / n, 0.5, 5.0 * sqrt(1.0 / 12.0 / n), "mean of uniform");
    check_abs(s2 / n - (s / n) * (s / n), 1.0 / 12.0, 1e-3, "variance of uniform");
}

/* The first ten points in three dimensions, in Gray-code order, as published with the direction
 * numbers (Joe & Kuo 2008; e.g. the Python reader distributed with new-joe-kuo-6.21201). */
static void sobol_matches_published_points(void **state)
{
    const double published[10][3] = {{0, 0, 0},          {0.5, 0.5, 0.5},       {0.75, 0.25, 0.25},
                                     {0.25, 0.75, 0.75}, {0.375, 0.375, 0.625}, {0.875, 0.875, 0.125},
                                     {0.625, 0.125, 0.875}, {0.125, 0.625, 0.375}, {0.1875, 0.3125, 0.9375},
                                     {0.6875, 0.8125, 0.4375}};
    for (uint32_t i = 0; i < 10; i++)
        for (int d = 0; d < 3; d++)
            assert_true(sobol_u32(i ^ (i >> 1), d) * 0x1.0p-32 == published[i][d]);
}

/* Scrambled or not, the first 2^m points put one point in each of 2^m equal cells of every
 * coordinate, and in each 2^a x 2^(m-a) box of the first two coordinates (a (0, m, 2)-net); the
 * scramble's points are uniform (mean 1/2 over many seeds); rng_for_qmc hands them out first. */
static void sobol_owen_points_are_stratified(void **state)
{
    enum { M = 10, N = 1 << M };
    static int cell[N];
    for (uint64_t seed = 0; seed < 4; seed++) {
        for (int d = 0; d < FM_SOBOL_DIMS; d++) {
            for (int i = 0; i < N; i++)
                cell[i] = 0;
            for (uint32_t i = 0; i < N; i++) {
                double u = seed ? sobol_owen(i, d, seed, seed == 1 ? 24 : M) : sobol_u32(i, d) * 0x1.0p-32;
                assert_true(u >= 0.0 && u < 1.0);
                cell[(int)(u * N)]++;
            }
            for (int i = 0; i < N; i++)
                if (cell[i] != 1)
                    fail_msg("seed %d dim %d: cell %d holds %d points", (int)seed, d, i, cell[i]);
        }
        for (int a = 0; a <= M; a++) {
            for (int i = 0; i < N; i++)
                cell[i] = 0;
            for (uint32_t i = 0; i < N; i++) {
                double u = sobol_owen(i, 0, seed + 10, M), v = sobol_owen(i, 1, seed + 10, M);
                cell[(int)(u * (1 << a)) * (1 << (M - a)) + (int)(v * (1 << (M - a)))]++;
            }
            for (int i = 0; i < N; i++)
                if (cell[i] != 1)
                    fail_msg("seed %d: box %d of the 2^%d x 2^%d net holds %d points", (int)seed, i, a, M - a,
                             cell[i]);
        }
    }
    const int seeds = 20000;
    double s = 0.0;
    for (int k = 0; k < seeds; k++)
        s += sobol_owen(5, 3, (uint64_t)k, 4);
    check_abs(s / seeds, 0.5, 5.0 * sqrt(1.0 / 12.0 / seeds), "mean of scrambled points");
    assert_int_equal(sobol_levels(N), M);
    assert_int_equal(sobol_levels(N + 1), M + 1);
    rng r = rng_for_qmc(3, 4, 5, 64), plain = rng_for(3, 4, 5);
    uint64_t key = r.qmc_seed;
    uint32_t point = sobol_shuffle(5, 6, key);
    for (int d = 0; d < FM_SOBOL_DIMS; d++)
        assert_true(rng_uniform(&r) == sobol_owen(point, d, key, 6));
    assert_true(rng_uniform(&r) == rng_uniform(&plain)); /* then the sample's own PCG stream */
}

/* The sample order shuffle is a bijection of [0, 2^levels) that keeps the digits above. */
static void sobol_shuffle_is_a_permutation(void **state)
{
    enum { M = 10, N = 1 << M };
    static int seen[N];
    int moved = 0;
    for (uint32_t i = 0; i < N; i++) {
        uint32_t j = sobol_shuffle(i, M, 77);
        assert_true(j < N);
        seen[j]++;
        moved += j != i;
    }
    for (int i = 0; i < N; i++)
        assert_int_equal(seen[i], 1);
    assert_true(moved > N / 2);
    assert_int_equal(sobol_shuffle(3u << M | 5u, M, 77) >> M, 3);
}

/* The tabulated scramble draws the same numbers as sobol_owen, bit for bit, and a stream given the
 * table the same as without it; more levels than the table holds leave it unused. */
static void sobol_table_matches_hashed_scramble(void **state)
{
    static sobol_scramble table;
    for (int levels = 1; levels <= FM_SOBOL_TABLE_LEVELS; levels += 3)
        for (uint64_t seed = 1; seed < 4; seed++) {
            sobol_scramble_init(&table, seed * 0x9E3779B97F4A7C15ull, levels);
            assert_int_equal(table.levels, levels);
            for (uint32_t i = 0; i < 1u << levels; i++) /* every point: the table is built in Gray-code order */
                for (int d = 0; d < FM_SOBOL_DIMS; d++)
                    assert_true(sobol_owen_tabulated(&table, i, d) ==
                                sobol_owen(i, d, seed * 0x9E3779B97F4A7C15ull, levels));
            sobol_scramble_free(&table);
        }
    sobol_scramble_init(&table, rng_qmc_seed(3, 4), sobol_levels(64));
    rng r = rng_for_qmc(3, 4, 5, 64), hashed = rng_for_qmc(3, 4, 5, 64);
    rng_use_scramble(&r, &table);
    assert_non_null(r.qmc_table);
    for (int d = 0; d < FM_SOBOL_DIMS + 2; d++)
        assert_true(rng_uniform(&r) == rng_uniform(&hashed));
    sobol_scramble_free(&table);
    sobol_scramble_init(&table, 7, FM_SOBOL_TABLE_LEVELS + 1);
    assert_int_equal(table.levels, 0);
    rng big = rng_for_qmc(3, 4, 5, 1u << (FM_SOBOL_TABLE_LEVELS + 1));
    rng_use_scramble(&big, &table);
    assert_null(big.qmc_table);
}

static void count_items(void *ctx, int64_t begin, int64_t end, int thread)
{
    atomic_llong *sum = ctx;
    for (int64_t i = begin; i < end; i++)
        atomic_fetch_add(sum, i);
}

static void parallel_for_visits_every_item_once(void **state)
{
    for (int threads = 1; threads <= 4; threads++) {
        atomic_llong sum;
        atomic_init(&sum, 0);
        assert_int_equal(parallel_for(threads, 10007, 13, count_items, &sum, NULL, NULL), FM_OK);
        assert_true(atomic_load(&sum) == 10007LL * 10006LL / 2);
    }
    atomic_int cancel;
    atomic_init(&cancel, 1);
    atomic_llong sum;
    atomic_init(&sum, 0);
    assert_int_equal(parallel_for(2, 1000, 1, count_items, &sum, &cancel, NULL), FM_ERR_CANCELLED);
}

/* Ulps between two finite doubles of the same sign (or both zero). */
static double ulps(double a, double b)
{
    if (a == b)
        return 0.0;
    return fabs(a - b) / (nextafter(fmax(fabs(a), fabs(b)), INFINITY) - fmax(fabs(a), fabs(b)));
}

/* exp_array and expm1_array against libm's scalar functions: within the 4 ulp glibc states for its
 * vector functions, for every length (odd ones end on the scalar path) and over the range the
 * transmittances use (optical depths 0 to 745, where exp underflows), plus the edge values. */
static void exp_arrays_match_libm(void **state)
{
    double x[41] = {0}, e[41], m[41], worst_exp = 0.0, worst_expm1 = 0.0;
    for (int n = 0; n <= 41; n++) {
        for (int i = 0; i < n; i++)
            x[i] = -745.0 * pow((i + 0.37 * n) / 56.0, 3.0) + (i % 3 == 0 ? 1e-9 * i : 0.0);
        exp_array(x, e, n);
        expm1_array(x, m, n);
        for (int i = 0; i < n; i++) {
            worst_exp = fmax(worst_exp, ulps(e[i], exp(x[i])));
            worst_expm1 = fmax(worst_expm1, ulps(m[i], expm1(x[i])));
        }
    }
    print_message("exp_array %.2f ulp, expm1_array %.2f ulp\n", worst_exp, worst_expm1);
    if (worst_exp > 4.0 || worst_expm1 > 4.0)
        fail_msg("exp_array %.1f ulp, expm1_array %.1f ulp from libm", worst_exp, worst_expm1);
    /* edges: 0, tiny depths (expm1's reason to exist), darkness, in place */
    double edge[6] = {0.0, -1e-300, -1e-12, -INFINITY, -800.0, 2.0};
    exp_array(edge, e, 6);
    expm1_array(edge, m, 6);
    assert_true(e[0] == 1.0 && m[0] == 0.0);
    assert_true(m[1] == -1e-300 && fabs(m[2] / -1e-12 - 1.0) < 1e-12);
    assert_true(e[3] == 0.0 && m[3] == -1.0 && e[4] == 0.0);
    assert_true(ulps(e[5], exp(2.0)) <= 4.0);
    exp_array(edge, edge, 6);
    assert_true(edge[0] == 1.0 && edge[3] == 0.0 && ulps(edge[5], exp(2.0)) <= 4.0);
}

/* log_array against libm's log for every length 0-41 over transmittances 1e-87 to 1 (the sun
 * table's depths 0-200), the same 4 ulp bound; log 1 = 0 exactly, and in place. */
static void log_array_matches_libm(void **state)
{
    double x[41] = {0}, l[41], worst = 0.0;
    for (int n = 0; n <= 41; n++) {
        for (int i = 0; i < n; i++)
            x[i] = exp(-200.0 * pow((i + 0.37 * n) / 56.0, 3.0)) * (1.0 - 1e-9 * (i % 3));
        log_array(x, l, n);
        for (int i = 0; i < n; i++)
            worst = fmax(worst, ulps(l[i], log(x[i])));
    }
    print_message("log_array %.2f ulp\n", worst);
    if (worst > 4.0)
        fail_msg("log_array %.1f ulp from libm", worst);
    double edge[5] = {1.0, 1e-300, 0.5, 2.0, 1e-87};
    log_array(edge, edge, 5);
    assert_true(edge[0] == 0.0);
    assert_true(ulps(edge[1], log(1e-300)) <= 4.0 && ulps(edge[2], log(0.5)) <= 4.0);
    assert_true(ulps(edge[3], log(2.0)) <= 4.0 && ulps(edge[4], log(1e-87)) <= 4.0);
}

/* platform_create_unique: a new empty file per call, with a new file's permissions (the umask
 * applied to 0666, not mkstemp's 0600), and -1 in a folder that does not exist. */
static void unique_files_have_new_file_permissions(void **state)
{
    mode_t mask = umask(022);
    char a[64], b[64];
    snprintf(a, sizeof a, "%s/fm-unique-XXXXXX", platform_temp_dir());
    snprintf(b, sizeof b, "%s/fm-unique-XXXXXX", platform_temp_dir());
    assert_int_equal(platform_create_unique(a), 0);
    assert_int_equal(platform_create_unique(b), 0);
    assert_string_not_equal(a, b);
    struct stat st;
    assert_int_equal(stat(a, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644);
    assert_int_equal(st.st_size, 0);
    remove(a);
    remove(b);
    char missing[] = "/nonexistent-fm-folder/x-XXXXXX";
    assert_int_equal(platform_create_unique(missing), -1);
    umask(mask);
}

/* An empty file in dir last modified age_s ago. */
static void plant(const char *dir, const char *name, double age_s)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fclose(f);
    struct utimbuf t = {.actime = time(NULL) - (time_t)age_s, .modtime = time(NULL) - (time_t)age_s};
    assert_int_equal(utime(path, &t), 0);
}

/* Whether dir holds a file of that name. */
static int exists(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

/* A sealed file's write removes the temporaries that killed writers of files of its kind left (its
 * name but for the key and the six unique characters) once they are an hour old; not a fresh one
 * (a writer at work), nor any other file. */
static void sealed_file_write_removes_stale_temporaries(void **state)
{
    char dir[256];
    snprintf(dir, sizeof dir, "%s/fm-sealed-XXXXXX", platform_temp_dir());
    assert_non_null(mkdtemp(dir));
    const char *key = "0123456789abcdef0123456789abcdef";
    const char *old[] = {"cloud-fedcba9876543210fedcba9876543210.fmcloud.Ab12Cd",
                         "cloud-0123456789abcdef0123456789abcdef.fmcloud.zz9Y0x"};
    const char *kept[] = {"cloud-fedcba9876543210fedcba9876543210.fmcloud.Qq11Ww", /* fresh */
                          "cloud-fedcba9876543210fedcba9876543210.fmcloud.Ab12C",
                          "cloud-fedcba9876543210fedcba9876543210.fmcloud.Ab12C_",
                          "cloud-FEDCBA9876543210fedcba9876543210.fmcloud.Ab12Cd",
                          "cloud-fedcba9876543210fedcba9876543210.fmcloud",
                          "notes-fedcba9876543210fedcba9876543210.fmcloud.Ab12Cd",
                          "cloud-fedcba9876543210fedcba9876543210.fmlive.Ab12Cd"};
    for (int i = 0; i < 2; i++)
        plant(dir, old[i], 7200.0);
    plant(dir, kept[0], 60.0);
    for (int i = 1; i < 7; i++)
        plant(dir, kept[i], 7200.0);
    char path[512];
    snprintf(path, sizeof path, "%s/cloud-%s.fmcloud", dir, key);
    const sealed_format format = {"FMTEST01", 1, 7, "test table", "another table"};
    assert_int_equal(sealed_file_write(path, &format, key, "payload", 7, NULL), FM_OK);
    for (int i = 0; i < 2; i++)
        assert_false(exists(dir, old[i]));
    for (int i = 0; i < 7; i++)
        assert_true(exists(dir, kept[i]));
    assert_true(exists(dir, "cloud-0123456789abcdef0123456789abcdef.fmcloud"));
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -r '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gauss_legendre_is_exact_for_polynomials),
        cmocka_unit_test(rng_streams_are_deterministic_and_uniform),
        cmocka_unit_test(sobol_matches_published_points),
        cmocka_unit_test(sobol_owen_points_are_stratified),
        cmocka_unit_test(sobol_shuffle_is_a_permutation),
        cmocka_unit_test(sobol_table_matches_hashed_scramble),
        cmocka_unit_test(parallel_for_visits_every_item_once),
        cmocka_unit_test(exp_arrays_match_libm),
        cmocka_unit_test(log_array_matches_libm),
        cmocka_unit_test(unique_files_have_new_file_permissions),
        cmocka_unit_test(sealed_file_write_removes_stale_temporaries),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
