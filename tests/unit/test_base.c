/* Base utilities: Gauss-Legendre exactness, random-number streams, the parallel loop. */
#include "check.h"

#include "base/quadrature.h"
#include "base/rng.h"
#include "base/threads.h"

#include <math.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gauss_legendre_is_exact_for_polynomials),
        cmocka_unit_test(rng_streams_are_deterministic_and_uniform),
        cmocka_unit_test(parallel_for_visits_every_item_once),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
