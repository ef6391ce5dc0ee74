/* The fast path's column tables and their comparison against the reference (column_tables.h). */
#include "column_tables.h"

#include "check.h"

#include <math.h>
#include <stdlib.h>

void column_tables_start(const fm_sky *sky, uint64_t seed, int from_above, column_tables *t)
{
    t->rp = fm_render_params_default();
    t->rp.width = 64;
    t->rp.seed = seed;
    t->ms = (ms_table){0};
    t->job = (render_job){
        .sky = sky, .params = &t->rp, .ms = &t->ms, .fine_fog_table = 1, .fog_from_above = from_above};
    fm_error err;
    assert_int_equal(render_start(&t->job, &err), FM_OK);
    assert_int_equal(render_twilight(&t->job, &t->tw, &err), FM_OK);
    t->job.twilight = t->tw;
}

void column_tables_make(column_tables *t)
{
    fm_error err;
    assert_int_equal(render_fast_tables(&t->job, asin(t->job.sky->sun_dir.z), &err), FM_OK);
    assert_int_equal(t->job.paths_per_node, 0); /* the column's table, not paths */
}

void column_tables_free(column_tables *t)
{
    free(t->tw);
    render_tables_free(&t->job);
    fm_image_destroy(t->job.img);
}

double column_tables_radiance(const column_tables *t, double e, double phi)
{
    float v[1];
    sky_grid_lookup(&t->job.ss, e, phi, v);
    double L = v[0];
    sky_grid_lookup(&t->ms.grid, e, phi, v);
    return L + v[0];
}

static int print_against_reference(double fast, double ref, double se, double rel, const char *what, int flag)
{
    const int ok = fabs(fast - ref) <= rel * ref + 3.0 * se;
    print_message("%s: fast path %.5g, reference %.5g +- %.2f%% (%+.2f%%)%s\n", what, fast, ref, 100.0 * se / ref,
                  100.0 * (fast / ref - 1.0), ok || !flag ? "" : "  OUTSIDE");
    return ok;
}

int within_reference(double fast, double ref, double se, double rel, const char *what)
{
    return print_against_reference(fast, ref, se, rel, what, 1);
}

void check_within_reference(double fast, double ref, double se, double rel, const char *what)
{
    print_against_reference(fast, ref, se, rel, what, 0);
    check_abs(fast, ref, rel * ref + 3.0 * se, what);
}
