#include "transport/path.h"

#include "base/checks.h"
#include "base/exp_array.h"
#include "base/threads.h"
#include "base/units.h"
#include "phase/phase.h"
#include "spectrum/spectral.h"
#include "transport/deck_base.h"
#include "transport/free_flight.h"
#include "transport/path_direction.h"
#include "transport/shadow_flight.h"
#include "transport/sunlit_segment.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

/* ---- Roulette and splitting: the weight a path carries ---------------------------------------- */

/* Russian roulette plays once a path's weight (its largest spectral weight q_k w_k W / mean(q)) is
 * below this, and raises survivors to it, not to 1: a path sent into an unlikely direction by the
 * sun guide has a weight << 1 on purpose, and raising it to 1 would undo the guide's gain
 * (docs/decisions/2026-12-06-russian-roulette.md). */
#define FM_ROULETTE_THRESHOLD 0.1
/* Deep twilight's light-led roulette keeps at least this share of the paths at each vertex, so a
 * survivor's weight grows at most tenfold per vertex (docs/decisions/2026-12-06-light-led-roulette.md). */
#define LIGHT_LED_MIN_SURVIVAL 0.1
/* Deep twilight splits a path whose weight has passed SPLIT_WEIGHT into at most SPLIT_COPIES copies
 * that share it, and each path may make SPLIT_BUDGET copies beyond itself: the heavy tail of its
 * path estimates, left whole, has no variance (docs/decisions/2026-12-06-path-splitting.md).  A
 * copy inherits what is left of that budget, which bounds the waiting copies (PATH_STACK) but not
 * their number: where nearly every vertex passes the split weight the copies of copies multiply, so
 * a path and all its copies make at most SPLIT_TOTAL together.  The light-led split at a vertex may
 * take a larger weight (path_context.vertex_split_weight: the preview's, in haze fewer copies for
 * less noise per CPU second, docs/decisions/2026-12-07-deep-split-in-haze.md). */
#define SPLIT_WEIGHT 3.0
#define SPLIT_COPIES 4
#define SPLIT_BUDGET 32
#define SPLIT_TOTAL 1024
/* exp(-600): the weight behind an absorption optical depth of 600, far below any light a map holds */
#define OPAQUE_WEIGHT 2.65e-261

/* A path's weight as roulette and splitting weigh it: its largest spectral weight q_k w_k W / mean(q). */
static double path_weight(double W, const double *q, const double *w, int K)
{
    return spectral_max_product(q, w, K) * (W / spectral_mean(q, K));
}

/* Russian roulette on the path's weight times lift (1, or the light-led roulette's light_lift);
 * returns 0 if the path dies, else scales W by 1 / survival.  At least min_survive of the paths
 * live on, at most cap (survival_cap). */
static int roulette(double *W, const double *q, const double *w, int K, double cap, double lift, double min_survive,
                    rng *r)
{
    double m = spectral_max_product(q, w, K) * (*W / spectral_mean(q, K) * lift);
    double survive = fmin(m / FM_ROULETTE_THRESHOLD, cap);
    survive = survive > min_survive ? survive : min_survive;
    if (survive >= 1.0)
        return 1;
    if (!(survive > 0.0) || rng_uniform(r) >= survive)
        return 0;
    *W /= survive;
    return 1;
}

/* Keeps the pdf ratios q within range: only their ratios to their mean matter. */
static void renormalise(double *q, int K)
{
    double m = spectral_max(q, K);
    if (m > 1e100 || (m < 1e-100 && m > 0.0))
        spectral_divide(q, m, K);
}

/* The light-led roulette's lift at x: how much more light x receives (orders 1 and 2,
 * shadow_flight_light) than the path's first point did, at least 1.  A guided flight that lands in
 * bright light has a small weight (its pdf follows that light, shadow_flight.h), and a roulette on
 * the weight alone would end it; on weight x lift it plays on the light the path will bring. */
static double light_lift(const path_context *ctx, vec3 x, double start_light)
{
    if (!(start_light > 0.0))
        return 1.0; /* not light-led: the plain roulette */
    double r = v3_length(x), light = shadow_flight_light(ctx->shadow_flights, r, v3_dot(x, ctx->sun_dir) / r);
    return light > start_light ? light / start_light : 1.0;
}

/* How many copies a path of weight m (as roulette weighs it, times lift) splits into past the split
 * weight `at`: 1 for none. */
static int split_copies(double m, double at, int splits_left)
{
    if (!(m > at) || splits_left <= 0)
        return 1;
    int copies = m < SPLIT_COPIES * at ? (int)ceil(m / at) : SPLIT_COPIES;
    return copies - 1 < splits_left ? copies : splits_left + 1;
}

/* ---- The path's state and the tracer ----------------------------------------------------------- */

/* The medium at a point: species densities, scattering and extinction coefficients. */
typedef struct vertex_medium {
    double n[FM_MAX_SPECIES];
    spectral sig_s, sig_t;
} vertex_medium;

/* What a path does next. */
typedef enum path_stage {
    STAGE_FLIGHT,    /* fly from pos along d */
    STAGE_VERTEX,    /* scatter at pos, arrived along d (path_trace_from, a copy split at a vertex) */
    STAGE_DIRECTION, /* draw the next direction at the vertex pos in `medium`, arrived along d */
} path_stage;

/* Everything a path carries from one event to the next. */
typedef struct path_state {
    spectral q;          /* each wavelength's path pdf relative to the hero's (spectral MIS) */
    spectral w;          /* each wavelength's f / p */
    double W;            /* weight shared by every wavelength: roulette's and splitting's */
    double start_light;  /* light-led roulette: the light at the path's first point (> 0), else 0 */
    int order;           /* interactions so far */
    int splits_left;     /* copies it may still split into */
    int vertices_done;   /* it has left a vertex: roulette may play */
    int counted;         /* STAGE_VERTEX: the vertex's sunlight was counted (by the path it split from) */
    path_stage stage;
    vec3 pos, d;         /* m, Earth-centred; unit direction */
    vertex_medium medium; /* at pos, for STAGE_DIRECTION */
} path_state;

/* Paths waiting their turn: the copies of split paths and the paths they split from, run last in
 * first out, so in the order a recursion into each copy would run them (the same random numbers).
 * Each split pushes at most two entries and lowers the budget of all it pushes by at least one. */
#define PATH_STACK (2 * SPLIT_BUDGET + 1)
typedef struct waiting_path {
    path_state state;
    int copies; /* runs of this state still to go */
} waiting_path;

/* What stays the same over one call of path_trace: the context, the hero wavelength, the random
 * numbers, where contributions go (for each of the walk's suns, path_context.suns), and the waiting
 * paths. */
typedef struct tracer {
    const path_context *ctx;
    const atmosphere *atm;
    int K, h;
    rng *r;
    double *const *L, *const *L_later;
    int light_led;      /* deep twilight's roulette at the new vertex (path_context.light_led_roulette) */
    double min_survive; /* the roulette's floor: LIGHT_LED_MIN_SURVIVAL when light-led, else 0 */
    double vertex_split; /* the light-led split's weight (path_context.vertex_split_weight) */
    int copies_made;    /* by the path and its copies, together (at most SPLIT_TOTAL) */
    int waiting;
    waiting_path stack[PATH_STACK];
} tracer;

/* The copies p may still split into: its own budget's, within what is left of the whole path's. */
static int splits_left(const tracer *tr, const path_state *p)
{
    int total_left = SPLIT_TOTAL - tr->copies_made;
    return p->splits_left < total_left ? p->splits_left : total_left;
}

static void push_path(tracer *tr, const path_state *p, int copies)
{
    assert(tr->waiting < PATH_STACK);
    tr->stack[tr->waiting].state = *p;
    tr->stack[tr->waiting++].copies = copies;
}

/* The next waiting path into *p; 0 when none is left. */
static int pop_path(tracer *tr, path_state *p)
{
    if (tr->waiting == 0)
        return 0;
    waiting_path *top = &tr->stack[tr->waiting - 1];
    *p = top->state;
    if (--top->copies == 0)
        tr->waiting--;
    return 1;
}

/* The roulette's largest survival probability at a path's order: past order 8 at most 95% survive
 * (the longest paths end), except in a dense medium (the last vertex's scattering coefficient at
 * least FM_DENSE_SIGMA_PER_M: cloud or fog, an optical depth of 1 per km) where flights can leave
 * through the top: there paths end by themselves (thick segments let them out) and a thick cloud's
 * light needs hundreds of orders, so all survive that the weight lets live, up to order
 * CAP_ORDER_DENSE (a guard).  Deep twilight's shadow flights never let a path out, but none leaves
 * from cloud or fog (flight_placed). */
#define CAP_ORDER 8
#define CAP_ORDER_DENSE 100000
static double survival_cap(const tracer *tr, const path_state *p)
{
    int dense = p->medium.sig_s[tr->h] >= FM_DENSE_SIGMA_PER_M;
    return p->order > (dense ? CAP_ORDER_DENSE : CAP_ORDER) ? 0.95 : 1.0;
}

/* The path's throughput is W / mean(q) q_k w_k: its scale here. */
static double throughput_scale(const tracer *tr, const path_state *p) { return p->W / spectral_mean(p->q, tr->K); }

/* Where the contributions of `order` for the walk's sun s go: L, or L_later for orders 3 and up when
 * it is given. */
static double *light_sink(tracer *tr, int order, int s)
{
    return tr->L_later && order > 2 ? tr->L_later[s] : tr->L[s];
}

static void medium_at(const atmosphere *atm, double radius, vertex_medium *m)
{
    atmosphere_densities(atm, radius, m->n);
    atmosphere_coefficients_from_densities(atm, m->n, m->sig_s, m->sig_t);
}

/* ---- Free flights ------------------------------------------------------------------------------ */

/* What a tentative collision turns out to be: the path scatters there, flies on, or ends (absorption
 * has taken its weight below anything a map holds). */
typedef enum collision { COLLISION_SCATTER, COLLISION_NULL, COLLISION_OPAQUE } collision;

/* A tentative collision at distance t along seg, in the majorant's shell (delta tracking), or
 * placed there by a shadow flight (shell SHELL_PLACED: a scattering by construction, its weight
 * applied by the flight). */
typedef collision (*collision_fn)(tracer *tr, path_state *p, const ray_segment *seg, double t, int shell);
#define SHELL_PLACED (-1)

/* How a free flight ends: at a scattering, at the segment's end (the ground or the top), or with
 * the path (an opaque medium, or nothing to collide with on a segment forced to collide). */
typedef enum flight { FLIGHT_SCATTER, FLIGHT_END_OF_SEGMENT, FLIGHT_PATH_ENDS } flight;

/* At a tentative collision of delta tracking the hero scatters with probability sigma_s / majorant;
 * otherwise absorption and null collisions continue together, with probability
 * (majorant - sigma_s) / majorant, and the surviving fraction (majorant - sigma_t) /
 * (majorant - sigma_s) is a weight, not a coin flip, so absorbing layers (ozone, soot) end no paths
 * (unless absorption leaves nothing: COLLISION_OPAQUE).  Every wavelength's pdf of the event enters q. */
static collision collide(tracer *tr, path_state *p, const ray_segment *seg, double t, int shell)
{
    const int K = tr->K, h = tr->h;
    vertex_medium *m = &p->medium;
    medium_at(tr->atm, ray_segment_radius(seg, t), m);
    if (shell == SHELL_PLACED)
        return COLLISION_SCATTER;
    const double *maj = tr->atm->shell_majorant[shell];
    if (rng_uniform(tr->r) * maj[h] < m->sig_s[h]) {
        spectral_mul_ratio(p->q, m->sig_s, m->sig_s[h], K);
        return COLLISION_SCATTER;
    }
    double cont_h = maj[h] - m->sig_s[h];
    for (int k = 0; k < K; k++) {
        double cont = maj[k] - m->sig_s[k];
        p->w[k] *= cont > 0.0 ? larger(maj[k] - m->sig_t[k], 0.0) / cont : 0.0;
        p->q[k] *= cont / cont_h;
    }
    renormalise(p->q, K); /* a flight through thick haze makes hundreds of these */
    /* an opaque medium: tracking a weight that absorption took below e^-600 on to the segment's end
     * could take millions of collisions, for nothing */
    return path_weight(p->W, p->q, p->w, K) > OPAQUE_WEIGHT ? COLLISION_NULL : COLLISION_OPAQUE;
}

/* Segments that would leave through the top are forced to collide only below this majorant optical
 * depth: beyond it 1 - e^-depth is nearly 1 and forcing gains nothing, and inside a thick cloud
 * a path that may never leave would end only by roulette (survival_cap). */
#define FORCE_MAX_DEPTH 4.0

/* A forced collision on a segment that would leave through the top: the first tentative collision
 * is drawn inside it.  Each wavelength's technique would do the same with its own probability F_k
 * = 1 - exp(-majorant depth_k) of colliding: weight f/p = F_k, and F_k enters that technique's pdf.
 * Beyond FORCE_MAX_DEPTH a technique does not force (F_k taken as 1): the flight may leave.
 * Returns 0 when the segment's majorant depth is nil (nothing to collide with), else the optical
 * depth to the first tentative collision in *tau. */
static int force_collision(tracer *tr, path_state *p, const ray_segment *seg, double *tau)
{
    const int K = tr->K, h = tr->h;
    spectral depth, force;
    free_flight_majorant_depth(tr->atm, seg, 0.0, seg->t_end, depth);
    if (!(depth[h] > 1e-12))
        return 0;
    spectral_negate(force, depth, K);
    expm1_array(force, force, K);
    spectral_negate(force, force, K);
    for (int k = 0; k < K; k++) /* a wavelength that would not force: an ordinary flight, F_k = 1 */
        if (depth[k] > FORCE_MAX_DEPTH)
            force[k] = 1.0;
    spectral_mul(p->w, force, K);
    for (int k = 0; k < K; k++) /* a wavelength the medium does not touch cannot make this path */
        p->q[k] = force[k] > 0.0 ? p->q[k] * force[h] / force[k] : 0.0;
    assert(is_probability(force[h]));
    *tau = -log1p(-rng_uniform(tr->r) * force[h]);
    return 1;
}

/* q_k *= exp(x_k), x destroyed.  Behind thick haze a flight's depths at two wavelengths can differ
 * by more than exp holds (an aerosol layer of optical depth 19 at 550 nm: over 700 between blue and
 * red), and inf times a nil q_k, or inf / inf in renormalise, is NaN.  Then the products come from
 * logarithms, scaled so that the largest is 1 (only the ratios of q count); a nil q_k stays nil. */
#define EXP_SAFE 600.0
static void mul_exp(double *q, double *x, int K)
{
    double lo = x[0], hi = x[0];
    for (int k = 1; k < K; k++) {
        lo = lo < x[k] ? lo : x[k];
        hi = hi > x[k] ? hi : x[k];
    }
    if (lo > -EXP_SAFE && hi < EXP_SAFE) {
        exp_array(x, x, K);
        spectral_mul(q, x, K);
        return;
    }
    double most = -HUGE_VAL;
    for (int k = 0; k < K; k++) {
        x[k] = q[k] > 0.0 ? log(q[k]) + x[k] : -HUGE_VAL;
        most = most > x[k] ? most : x[k];
    }
    assert(most > -HUGE_VAL && most < HUGE_VAL); /* renormalise keeps the largest q near 1 */
    for (int k = 0; k < K; k++)
        q[k] = exp(x[k] - most);
}

/* Delta tracking from the optical depth tau at the hero's majorant until `collide` scatters the path
 * or the segment ends.  A flight's pdf for wavelength k is exp(-majorant depth_k) times the pdf of
 * its events: the depths relative to the hero's are summed over the flight and enter q at its end,
 * one exp per wavelength per flight, not per tentative collision. */
static flight delta_tracking(tracer *tr, path_state *p, const ray_segment *seg, double tau,
                             collision_fn on_collision, double *t)
{
    const int K = tr->K, h = tr->h;
    spectral pending = {0}, depth;
    flight end = FLIGHT_END_OF_SEGMENT;
    *t = 0.0;
    for (;;) {
        int shell;
        int collided = free_flight_advance(tr->atm, seg, *t, tau, h, t, depth, &shell);
        spectral_add_difference(pending, depth[h], depth, K);
        if (!collided)
            break; /* reached the ground or the top */
        collision c = on_collision(tr, p, seg, *t, shell);
        if (c == COLLISION_OPAQUE)
            return FLIGHT_PATH_ENDS;
        if (c == COLLISION_SCATTER) {
            end = FLIGHT_SCATTER;
            break;
        }
        tau = -log1p(-rng_uniform(tr->r));
    }
    mul_exp(p->q, pending, K);
    renormalise(p->q, K);
    return end;
}

/* The path's next interaction along seg: a scattering at *t (the medium there in p->medium), the
 * segment's end (the ground, or out through the top), or the path's end.  In deep
 * twilight the shadow flights place it toward the light; otherwise delta tracking, its first
 * collision forced inside a segment that would leave through the top (thin air's paths stay
 * useful). */
/* Whether deep twilight's shadow flight places the segment's next vertex: not from a point in cloud or
 * fog (path_cloud_sigma), where the next vertex lies a free path away and the light the flight aims at
 * beyond the layer.  A flight's cells there are far longer than a free path, and a vertex it places
 * by the physical part of its density weighs more than 1: over the tens of vertices of a path in fog
 * the weights' second moment grew geometrically (docs/decisions/2026-12-07-fog-reference.md). */
static int flight_placed(const tracer *tr, const ray_segment *seg)
{
    if (!tr->ctx->shadow_flights)
        return 0;
    double n[FM_MAX_SPECIES], sig_s = 0.0;
    atmosphere_densities(tr->atm, v3_length(seg->origin), n);
    for (int c = 0; c < tr->atm->scattering_count; c++)
        sig_s += tr->atm->species[c].sigma_s[tr->h] * n[c];
    return sig_s < path_cloud_sigma(tr->ctx);
}

static flight free_flight(tracer *tr, path_state *p, const ray_segment *seg, collision_fn on_collision, double *t)
{
    const path_context *ctx = tr->ctx;
    double tau;
    if (flight_placed(tr, seg)) {
        *t = 0.0;
        if (!shadow_flight(ctx, ctx->shadow_flights, seg, tr->r, p->w, t))
            return FLIGHT_END_OF_SEGMENT; /* the ground */
        return on_collision(tr, p, seg, *t, SHELL_PLACED) == COLLISION_SCATTER ? FLIGHT_SCATTER : FLIGHT_PATH_ENDS;
    }
    if (!seg->hits_ground && !ctx->deck) {
        if (!force_collision(tr, p, seg, &tau))
            return FLIGHT_PATH_ENDS;
    } else {
        tau = -log1p(-rng_uniform(tr->r));
    }
    return delta_tracking(tr, p, seg, tau, on_collision, t);
}

/* ---- Vertices ---------------------------------------------------------------------------------- */

static int leave_scatter_vertex(tracer *tr, path_state *p);

/* The sunlight a scattering at x (arrived along p->d) passes on: E0 phase Tbar (sun_irradiance.h),
 * for each of the walk's suns but the first when `along` (its light counted along the segment). */
static void add_sunlight(tracer *tr, const path_state *p, vec3 x, int along)
{
    const path_context *ctx = tr->ctx;
    const double rad = v3_length(x);
    for (int s = along ? 1 : 0; s < path_sun_count(ctx); s++) {
        const vec3 sun_dir = path_sun(ctx, s);
        spectral tbar, phase;
        /* the table's nodes asked of memory first, read after the phase */
        const double mu_s = v3_dot(x, sun_dir) / rad;
        sun_cell cell;
        sun_irradiance_cell(ctx->sun_table, tr->atm, rad, mu_s, &cell);
        medium_phase(tr->atm, p->medium.n, v3_dot(p->d, sun_dir), phase, NULL);
        sun_irradiance_cell_transmittances(ctx->sun_table, tr->atm, ctx->sun, &cell, rad, mu_s, tbar);
        spectral_add_product5(light_sink(tr, p->order, s), throughput_scale(tr, p), p->q, p->w, phase,
                              tr->atm->grid.solar_irradiance, tbar, tr->K);
    }
}

/* The sunlight the Lambertian ground at the point of outward normal `normal` reflects:
 * albedo / pi E0 Thor, Thor the transmittance of the sun's horizontal irradiance (sun_irradiance.h);
 * the first sun left out when `along`, as add_sunlight. */
static void add_ground_sunlight(tracer *tr, const path_state *p, vec3 normal, int along)
{
    const path_context *ctx = tr->ctx;
    const int K = tr->K;
    spectral c;
    spectral_product(c, throughput_scale(tr, p), p->q, p->w, K);
    spectral_mul(c, tr->atm->ground_albedo, K);
    spectral_divide(c, FM_PI, K);
    for (int s = along ? 1 : 0; s < path_sun_count(ctx); s++) {
        spectral tbar, thor;
        sun_irradiance_lookup_ground(ctx->sun_table, tr->atm, ctx->sun, v3_dot(normal, path_sun(ctx, s)), tbar, thor);
        spectral_add_product(light_sink(tr, p->order, s), 1.0, c, tr->atm->grid.solar_irradiance, thor, K);
    }
}

/* A scattering at x in p->medium, arrived along p->d.  along: the segment's sunlight was counted
 * along it for the first sun (no point estimate here for it); late: the roulette plays here, after
 * the light is counted.  Returns 1 while the path goes on, 0 when it ended or waits on the stack
 * behind its copies. */
static int scatter_vertex(tracer *tr, path_state *p, vec3 x, int along, int late)
{
    const path_context *ctx = tr->ctx;
    assert(atmosphere_shell_contains(tr->atm, v3_length(x)));
    p->order++;
    if (p->order >= ctx->min_order && !p->counted)
        add_sunlight(tr, p, x, along);
    if (ctx->max_order > 0 && p->order >= ctx->max_order)
        return 0;
    const double lift = light_lift(ctx, x, p->start_light); /* 1 unless light-led */
    if (late && !roulette(&p->W, p->q, p->w, tr->K, survival_cap(tr, p), lift, tr->min_survive, tr->r))
        return 0;
    p->counted = 0;
    p->pos = x;
    int copies = ctx->shadow_flights && ctx->split_heavy_paths && tr->light_led
                     ? split_copies(path_weight(p->W, p->q, p->w, tr->K) * lift, tr->vertex_split, splits_left(tr, p))
                     : 1;
    if (copies == 1)
        return leave_scatter_vertex(tr, p);
    /* led by the light: each copy draws its own direction here, then the path itself */
    p->W /= copies;
    p->splits_left -= copies - 1;
    tr->copies_made += copies - 1;
    p->stage = STAGE_DIRECTION;
    push_path(tr, p, 1);
    path_state copy = *p;
    copy.stage = STAGE_VERTEX;
    copy.counted = copy.vertices_done = 1;
    copy.order--; /* the vertex counts it again */
    push_path(tr, &copy, copies - 1);
    return 0;
}

/* The next direction from the scattering vertex p->pos; a path heavy for its light splits into
 * copies that share the direction. */
static int leave_scatter_vertex(tracer *tr, path_state *p)
{
    const path_context *ctx = tr->ctx;
    const int K = tr->K;
    p->d = scatter_direction(ctx, p->pos, p->medium.n, p->medium.sig_s, p->d, tr->h, tr->r, p->q, p->w);
    renormalise(p->q, K);
    p->vertices_done = 1;
    p->stage = STAGE_FLIGHT;
    int copies = ctx->shadow_flights && ctx->split_heavy_paths
                     ? split_copies(path_weight(p->W, p->q, p->w, K), SPLIT_WEIGHT, splits_left(tr, p))
                     : 1;
    if (copies == 1)
        return 1;
    p->W /= copies;
    p->splits_left -= copies - 1;
    tr->copies_made += copies - 1;
    push_path(tr, p, copies); /* the copies, then the path itself: all alike */
    return 0;
}

/* A reflection at the ground point x (Lambertian, ground_albedo), as scatter_vertex. */
static int ground_vertex(tracer *tr, path_state *p, vec3 x, int along, int late)
{
    const path_context *ctx = tr->ctx;
    const atmosphere *atm = tr->atm;
    double rad = v3_length(x);
    vec3 normal = v3_scale(x, 1.0 / rad);
    p->order++;
    if (p->order == 1 && ctx->skip_ground_first)
        return 0;
    if (p->order >= ctx->min_order)
        add_ground_sunlight(tr, p, normal, along);
    if (ctx->max_order > 0 && p->order >= ctx->max_order)
        return 0;
    if (late && !roulette(&p->W, p->q, p->w, tr->K, survival_cap(tr, p), light_lift(ctx, x, p->start_light), tr->min_survive,
                          tr->r))
        return 0;
    if (!(spectral_dot(p->w, atm->ground_albedo, tr->K) > 0.0) ||
        !ground_direction(ctx, normal, tr->h, tr->r, p->q, p->w, &p->d))
        return 0;
    renormalise(p->q, tr->K);
    p->pos = v3_scale(normal, atm->bottom_radius_m);
    p->vertices_done = 1;
    p->stage = STAGE_FLIGHT;
    return 1;
}

/* ---- Segments ---------------------------------------------------------------------------------- */

/* Across the Earth's shadow (path_context.segment_sunlight): the next interaction's sunlight as the
 * segment's expected value, counted before the flight (for a shared walk's first sun).  Returns 1
 * when counted so, 0 when the vertex will take its point estimate, -1 when the path has reached
 * max_order. */
static int segment_sunlight_along(tracer *tr, const path_state *p, const ray_segment *seg)
{
    const path_context *ctx = tr->ctx;
    double umbra0, umbra1;
    if (!ctx->segment_sunlight || p->order + 1 < ctx->min_order)
        return 0;
    int along = segment_umbra(ctx, seg, &umbra0, &umbra1);
    int every = ctx->segment_sunlight == SEGMENT_SUNLIGHT_ALL ||
                (ctx->segment_sunlight == SEGMENT_SUNLIGHT_RISING && seg->s0 > 0.0);
    if (!along && every) {
        along = 1; /* no umbra to skip */
        umbra0 = umbra1 = seg->t_end;
    }
    if (!along)
        return 0;
    spectral S = {0};
    segment_sunlight(ctx, seg, umbra0, umbra1, tr->r, S);
    spectral_add_product(light_sink(tr, p->order + 1, 0), throughput_scale(tr, p), p->q, p->w, S, tr->K);
    return ctx->max_order > 0 && p->order + 1 >= ctx->max_order ? -1 : 1;
}

/* The light coming down from the deck's base at x, which the path reached along p->d: orders >= 3
 * (it has been scattered in the deck), counted only when the orders are not limited. */
static void add_deck_light(tracer *tr, const path_state *p, vec3 x)
{
    const path_context *ctx = tr->ctx;
    if (ctx->max_order > 0)
        return;
    spectral base = {0};
    deck_base_radiance(ctx->deck, x, p->d, ctx->sun_dir, 1.0, base);
    spectral_add_product(light_sink(tr, 3, 0), throughput_scale(tr, p), p->q, p->w, base, tr->K);
}

/* One segment from p->pos along p->d and the event that ends it.  Russian roulette plays once the
 * light the last direction found is counted: before the flight when the segment's sunlight was
 * counted along it, else at the next vertex after its point estimate (late), where a guided
 * direction's small weight pays off.  Returns 1 while the path goes on. */
static int fly_segment(tracer *tr, path_state *p)
{
    ray_segment seg;
    ray_segment_init(&seg, tr->atm, p->pos, p->d);
    int at_deck = deck_base_cut(tr->ctx->deck, &seg);
    int along = segment_sunlight_along(tr, p, &seg);
    if (along < 0)
        return 0;
    int late = p->vertices_done && (tr->light_led || !along);
    if (p->vertices_done && !late && !roulette(&p->W, p->q, p->w, tr->K, survival_cap(tr, p), 1.0, 0.0, tr->r))
        return 0;
    double t;
    flight end = free_flight(tr, p, &seg, collide, &t);
    if (end == FLIGHT_PATH_ENDS)
        return 0;
    if (end == FLIGHT_SCATTER)
        return scatter_vertex(tr, p, v3_madd(seg.origin, seg.dir, t), along, late);
    if (seg.hits_ground)
        return ground_vertex(tr, p, v3_madd(seg.origin, seg.dir, seg.t_end), along, late);
    if (at_deck)
        add_deck_light(tr, p, v3_madd(seg.origin, seg.dir, seg.t_end));
    return 0; /* left the atmosphere, or reached the deck */
}

/* A scattering at p->pos that begins a path (path_trace_from) or a copy of one split there. */
static int start_at_vertex(tracer *tr, path_state *p)
{
    medium_at(tr->atm, v3_length(p->pos), &p->medium);
    /* air that scatters nothing at the hero wavelength here (an absorbing-only atmosphere file) has
     * no phase function to draw the next direction from: no light this way */
    if (!(p->medium.sig_s[tr->h] > 0.0))
        return 0;
    return scatter_vertex(tr, p, v3_madd(p->pos, p->d, 0.0), 0, 0);
}

/* Runs one path, then the copies it split into and theirs, depth first; stops when the render is
 * cancelled (its sums are thrown away). */
static void trace(tracer *tr, path_state *p)
{
    do {
        int going = 1;
        while (going) {
            if (p->stage != STAGE_DIRECTION && parallel_cancelled())
                return;
            switch (p->stage) {
            case STAGE_FLIGHT: going = fly_segment(tr, p); break;
            case STAGE_VERTEX: going = start_at_vertex(tr, p); break;
            case STAGE_DIRECTION: going = leave_scatter_vertex(tr, p); break;
            }
        }
    } while (pop_path(tr, p));
}

/* A path from origin along dir (unit), with weights `weight` (or 1), at `stage`; returns the
 * copies it split into. */
static int trace_from(const path_context *ctx, vec3 origin, vec3 dir, const double *weight, path_stage stage,
                       int hero, rng *r, double *const *L, double *const *L_later)
{
    assert(is_unit(dir));
    /* a shared walk must not depend on the sun (path_context.suns), but for the rising segments of
     * its first */
    assert(ctx->suns <= PATH_SUNS_MAX &&
           (ctx->suns <= 1 ||
            ((ctx->segment_sunlight == SEGMENT_SUNLIGHT_NONE ||
              (ctx->segment_sunlight == SEGMENT_SUNLIGHT_RISING && ctx->max_order == 0 &&
               ctx->sun_dirs[0].x == ctx->sun_dir.x && ctx->sun_dirs[0].y == ctx->sun_dir.y &&
               ctx->sun_dirs[0].z == ctx->sun_dir.z)) &&
             !ctx->deck && !ctx->sky_guide && !ctx->shadow_flights)));
    const int K = ctx->atm->grid.count;
    tracer tr; /* field by field: its stack is large and needs no zeros */
    tr.ctx = ctx;
    tr.atm = ctx->atm;
    tr.K = K;
    tr.h = hero;
    tr.r = r;
    tr.L = L;
    tr.L_later = L_later;
    tr.light_led = ctx->shadow_flights && ctx->light_led_roulette;
    tr.min_survive = tr.light_led ? LIGHT_LED_MIN_SURVIVAL : 0.0;
    tr.vertex_split = ctx->vertex_split_weight > 0.0 ? ctx->vertex_split_weight : SPLIT_WEIGHT;
    tr.copies_made = 0;
    tr.waiting = 0;
    path_state p;
    p.W = 1.0;
    p.start_light = 0.0;
    p.order = p.vertices_done = p.counted = 0;
    p.splits_left = SPLIT_BUDGET;
    p.stage = stage;
    p.pos = origin;
    p.d = dir;
    spectral_fill(p.q, 1.0, K);
    spectral_fill(p.medium.sig_s, 0.0, K); /* survival_cap's medium until the first collision */
    if (weight)
        spectral_copy(p.w, weight, K);
    else
        spectral_fill(p.w, 1.0, K);
    if (tr.light_led) {
        double r0 = v3_length(origin);
        p.start_light = shadow_flight_light_and_ambient(ctx->shadow_flights, r0, v3_dot(origin, ctx->sun_dir) / r0);
        if (!(p.start_light > 0.0))
            p.start_light = 1e-300;
    }
    trace(&tr, &p);
    return tr.copies_made;
}

int path_trace(const path_context *ctx, vec3 origin, vec3 dir, int hero, rng *r, double *L)
{
    assert(ctx->suns <= 1);
    return trace_from(ctx, origin, dir, NULL, STAGE_FLIGHT, hero, r, &L, NULL);
}

int path_trace_from(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r, double *L,
                    double *L_later)
{
    assert(ctx->suns <= 1);
    return trace_from(ctx, x, dir, weight, STAGE_VERTEX, hero, r, &L, L_later ? &L_later : NULL);
}

int path_trace_from_suns(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r,
                         double *const *L, double *const *L_later)
{
    return trace_from(ctx, x, dir, weight, STAGE_VERTEX, hero, r, L, L_later);
}
