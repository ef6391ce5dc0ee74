#include "transport/free_flight.h"

#include "atmosphere/optical_depth.h"

#include <math.h>

void ray_segment_init(ray_segment *seg, const atmosphere *atm, vec3 origin, vec3 dir)
{
    seg->origin = origin;
    seg->dir = dir;
    seg->s0 = v3_dot(origin, dir);
    vec3 c = v3_cross(origin, dir);
    seg->p2 = v3_dot(c, c);
    double r = v3_length(origin);
    double mu = seg->s0 / r;
    seg->t_end = ray_distance_to_boundary(atm, r, mu, &seg->hits_ground);
}

int atmosphere_shell_of(const atmosphere *atm, double r)
{
    int lo = 0, hi = atm->shell_count - 1;
    if (r <= atm->shell_radius[0])
        return 0;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (atm->shell_radius[mid] <= r)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* Visits the pieces of [t0, t1] that lie in one shell each; calls back with (shell, ta, tb).
 * The callback returns nonzero to stop. */
typedef int (*piece_fn)(void *ctx, int shell, double ta, double tb);

static void walk_pieces(const atmosphere *atm, const ray_segment *seg, double t0, double t1, piece_fn fn, void *ctx)
{
    double t = t0;
    double s = t + seg->s0;
    /* Start in the shell of the midpoint of the first small step, so a start exactly on a
     * boundary picks the shell the ray is entering. */
    double r = sqrt(seg->p2 + s * s);
    int shell = atmosphere_shell_of(atm, r);
    if (s < 0.0 && shell > 0 && r <= atm->shell_radius[shell] * (1.0 + 1e-15))
        shell--;
    while (t < t1) {
        s = t + seg->s0;
        double r_in = atm->shell_radius[shell], r_out = atm->shell_radius[shell + 1];
        double s_next;
        int next_shell;
        if (s < 0.0 && r_in * r_in > seg->p2) {
            s_next = -sqrt(r_in * r_in - seg->p2); /* inbound: leave through the inner sphere */
            next_shell = shell - 1;
        } else {
            s_next = safe_sqrt(r_out * r_out - seg->p2); /* outbound (or turning inside) */
            next_shell = shell + 1;
        }
        double t_next = s_next - seg->s0;
        if (t_next <= t) /* rounding at a boundary: nudge into the next shell */
            t_next = t;
        if (t_next > t1)
            t_next = t1;
        if (fn(ctx, shell, t, t_next))
            return;
        t = t_next;
        if (next_shell < 0 || next_shell >= atm->shell_count)
            break;
        shell = next_shell;
    }
}

/* The majorant is each species at its largest density in the shell (atmosphere.h), so a majorant
 * depth is a sum over species of "majorant columns": one number per species per shell crossed, then
 * one product per wavelength and species (5 species and 41 wavelengths: a sixth of the work of a
 * depth per wavelength per shell). */
typedef struct depth_ctx {
    const atmosphere *atm;
    double col[FM_MAX_SPECIES];
} depth_ctx;

static void add_columns(const atmosphere *atm, int shell, double length, double *col)
{
    const double *n = atm->shell_density_max[shell];
    for (int c = 0; c < atm->species_count; c++)
        col[c] += n[c] * length;
}

static int add_depth(void *p, int shell, double ta, double tb)
{
    depth_ctx *c = p;
    add_columns(c->atm, shell, tb - ta, c->col);
    return 0;
}

void free_flight_majorant_depth(const atmosphere *atm, const ray_segment *seg, double t0, double t1, double *depth)
{
    depth_ctx c = {atm, {0}};
    walk_pieces(atm, seg, t0, t1, add_depth, &c);
    atmosphere_optical_depths(atm, c.col, depth);
}

typedef struct advance_ctx {
    const atmosphere *atm;
    double remaining;
    int hero, found, shell;
    double t;
    double col[FM_MAX_SPECIES];
} advance_ctx;

static int advance_piece(void *p, int shell, double ta, double tb)
{
    advance_ctx *c = p;
    const double *m = c->atm->shell_majorant[shell];
    double sigma = m[c->hero];
    double d = sigma * (tb - ta);
    if (d > c->remaining && sigma > 0.0) {
        c->found = 1;
        c->shell = shell;
        c->t = ta + c->remaining / sigma;
        tb = c->t;
    } else {
        c->remaining -= d;
    }
    add_columns(c->atm, shell, tb - ta, c->col);
    return c->found;
}

int free_flight_advance(const atmosphere *atm, const ray_segment *seg, double t0, double tau, int hero,
                        double *t_out, double *depth, int *shell)
{
    advance_ctx c = {atm, tau, hero, 0, 0, seg->t_end, {0}};
    walk_pieces(atm, seg, t0, seg->t_end, advance_piece, &c);
    atmosphere_optical_depths(atm, c.col, depth);
    *t_out = c.found ? fmin(c.t, seg->t_end) : seg->t_end;
    *shell = c.shell;
    return c.found;
}
