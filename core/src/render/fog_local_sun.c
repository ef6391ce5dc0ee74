#include "render/fog_local_sun.h"

#include "base/units.h"

#include <math.h>
#include <stdlib.h>

/* Steps along a view from the ground to the base: uniform in the arc, so denser near the ground
 * where the air is (at the horizon the height grows as the arc squared). */
#define VIEW_STEPS 32

double fog_local_sun_span(const atmosphere *atm, double base_m)
{
    return acos(atm->bottom_radius_m / (atm->bottom_radius_m + base_m));
}

/* The quadratic through the values at -1, 0, 1: in the logarithm (the twilit sky brightens
 * exponentially with the sun), in the value where one is not positive. */
typedef struct quadratic {
    double mid, slope, curve; /* b, c - a, a + c - 2 b */
    int log_space;
} quadratic;

static quadratic quadratic_through(double lo, double mid, double hi)
{
    const int log_space = lo > 0.0 && mid > 0.0 && hi > 0.0;
    const double a = log_space ? log(lo) : lo, b = log_space ? log(mid) : mid, c = log_space ? log(hi) : hi;
    return (quadratic){b, c - a, a + c - 2.0 * b, log_space};
}

/* Its value at x in [-1, 1]. */
static double quadratic_at(const quadratic *q, double x)
{
    const double v = q->mid + 0.5 * x * q->slope + 0.5 * x * x * q->curve;
    return q->log_space ? exp(v) : v;
}

static double interpolate(double lo, double mid, double hi, double x)
{
    const quadratic q = quadratic_through(lo, mid, hi);
    return quadratic_at(&q, x);
}

/* Along a view at elevation e: the arcs (rad) of the steps' middles and the base, and the weights at
 * each grid wavelength ([VIEW_STEPS + 1][K]): a step's the light it scatters seen through the air
 * before it (1 - e^-dtau under e^-tau: the air's source function near the deck's radiance, which
 * lights it), the base's what the air lets through. */
static void view_weights(const atmosphere *atm, double e, double base_m, double *arc, double *w)
{
    const int K = atm->grid.count;
    const double R = atm->bottom_radius_m, ce = cos(fmax(e, 0.0)), e0 = fmax(e, 0.0);
    const double end = acos(R * ce / (R + base_m)) - e0, d = end / VIEW_STEPS;
    double tau[FM_MAX_WAVELENGTHS] = {0}, ss[FM_MAX_WAVELENGTHS], st[FM_MAX_WAVELENGTHS];
    for (int s = 0; s < VIEW_STEPS; s++) {
        const double t = (s + 0.5) * d, c = cos(e0 + t);
        const double r = R * ce / c, ds = R * ce / (c * c) * d; /* m */
        atmosphere_coefficients(atm, r, ss, st);
        arc[s] = t;
        for (int k = 0; k < K; k++) {
            const double dt = st[k] * ds;
            w[s * K + k] = exp(-tau[k]) * -expm1(-dt);
            tau[k] += dt;
        }
    }
    arc[VIEW_STEPS] = end;
    for (int k = 0; k < K; k++)
        w[VIEW_STEPS * K + k] = exp(-tau[k]);
}

/* Table t's value at column c, wavelength k, at elevation e: linear in the sky rows' u. */
static double at_elevation(const sky_grid *g, const double *t, int c, int k, int K, double e)
{
    const double h = g->horizon_elevation, u = sqrt(fmax(0.0, fmin(e, 0.5 * FM_PI) - h) / (0.5 * FM_PI - h));
    const double x = u * (g->rows_sky - 1);
    const int r = x >= g->rows_sky - 1 ? g->rows_sky - 2 : (int)x;
    const double f = x - r;
    return (1.0 - f) * t[((size_t)r * g->cols + c) * K + k] + f * t[((size_t)(r + 1) * g->cols + c) * K + k];
}

void fog_local_sun_combine(const atmosphere *atm, const sky_grid *grid, double base_m, double span, double shift,
                           double toward, double tilt, const double *const at[FOG_LOCAL_SUNS], double *out)
{
    const int K = atm->grid.count, cols = grid->cols, nodes = sky_grid_nodes(grid);
    double arc[VIEW_STEPS + 1], w[(VIEW_STEPS + 1) * FM_MAX_WAVELENGTHS];
    for (int r = 0; r < grid->rows_sky; r++) {
        double e, phi;
        sky_grid_node_angles(grid, r * cols, &e, &phi);
        view_weights(atm, e, base_m, arc, w);
        for (int c = 0; c < cols; c++) {
            const int i = r * cols + c;
            sky_grid_node_angles(grid, i, &e, &phi);
            const double scale = shift * cos(phi) * (1.0 + 0.5 * (toward - 1.0) * (1.0 + cos(phi))) / span;
            double x[VIEW_STEPS + 1], et[VIEW_STEPS + 1];
            for (int s = 0; s <= VIEW_STEPS; s++) {
                /* toward the sun's azimuth the sun stands higher by the arc */
                x[s] = fmin(1.0, fmax(-1.0, scale * arc[s]));
                /* tilted: the view as seen there, higher over that point's horizon by the arc (its
                 * angle from the sun kept) */
                et[s] = e + tilt * arc[s];
            }
            for (int k = 0; k < K; k++) {
                const size_t n = (size_t)i * K + k;
                /* untilted, every step reads the node's own values */
                const quadratic own = tilt > 0.0 ? (quadratic){0} : quadratic_through(at[0][n], at[1][n], at[2][n]);
                double L = 0.0;
                for (int s = 0; s <= VIEW_STEPS; s++) {
                    const double v = tilt > 0.0 ? interpolate(at_elevation(grid, at[0], c, k, K, et[s]),
                                                              at_elevation(grid, at[1], c, k, K, et[s]),
                                                              at_elevation(grid, at[2], c, k, K, et[s]), x[s])
                                                : quadratic_at(&own, x[s]);
                    L += w[s * K + k] * v;
                }
                out[n] = L;
            }
        }
    }
    for (size_t n = (size_t)grid->rows_sky * cols * K; n < (size_t)nodes * K; n++)
        out[n] = at[1][n];
}

void fog_local_sun_combine_down(const atmosphere *atm, const sky_grid *grid, double observer_m, double top_m,
                                double span, double shift, const double *const at[FOG_LOCAL_SUNS], double *out)
{
    const int K = atm->grid.count, cols = grid->cols, nodes = sky_grid_nodes(grid);
    const double r0 = atm->bottom_radius_m + observer_m, r1 = atm->bottom_radius_m + top_m;
    for (size_t n = 0; n < (size_t)grid->rows_sky * cols * K; n++)
        out[n] = at[1][n];
    for (int i = grid->rows_sky * cols; i < nodes; i++) {
        double e, phi;
        sky_grid_node_angles(grid, i, &e, &phi);
        /* the arc to where the view meets the top: its depression d less the depression there (a view
         * above the top's horizon grazes it at the horizon's arc) */
        const double d = -e, c = r0 * cos(d) / r1, arc = c < 1.0 ? d - acos(c) : acos(r1 / r0);
        const double x = fmin(1.0, fmax(-1.0, shift * arc * cos(phi) / span));
        for (int k = 0; k < K; k++) {
            const size_t n = (size_t)i * K + k;
            out[n] = interpolate(at[0][n], at[1][n], at[2][n], x);
        }
    }
}
