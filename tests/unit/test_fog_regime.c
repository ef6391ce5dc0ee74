/* Which regime makes the multiple-scattering table (render/fog_regime.h): scenes of one or two layers,
 * an observer and a sun, one or more for each row of the table of bounds, each at the edges of its
 * bounds (0.01 degrees of sun on either side, or the layer's optical depth, base or the observer's
 * height just across).  The bounds are written here as numbers, not the header's constants, so that
 * moving a bound fails here as well as in the physics tests that measured it (the decision records
 * named in fog_regime.c). */
#include "check.h"

#include "base/units.h"
#include "render/fog_regime.h"

#include <math.h>
#include <stdio.h>

enum { FROM_ABOVE_OFF = 1, NOT_ON_GROUND = 2, REFERENCE = 4, TWILIGHT = 8 };

typedef struct regime_case {
    const char *what;
    fog_scene_layer layer[2];
    int layers;
    double altitude_m, sun_deg;
    int flags;
    fog_layers row;
    fog_regime regime;
} regime_case;

#define FOG(tau, h) {0.0, h, tau, 0}
#define WATER(base, h, tau) {base, h, tau, 0}
#define ICE(base, h, tau) {base, h, tau, 1}
#define AS WATER(3000.0, 1000.0, 10.0)
#define CS ICE(8000.0, 1500.0, 1.0)

static const regime_case cases[] = {
    {"clear sky", {FOG(0.0, 0.0)}, 0, 0.0, 30.0, 0, FOG_LAYERS_NONE, FOG_REGIME_PATHS},
    /* fog: visibility 1000 m at most (3.912 per km) */
    {"fog of visibility 1000 m", {FOG(3.912, 1000.0)}, 1, 0.0, 30.0, 0, FOG_LAYERS_FOG, FOG_REGIME_DAY},
    {"fog of visibility 1003 m", {FOG(3.9, 1000.0)}, 1, 0.0, 30.0, 0, FOG_LAYERS_NONE, FOG_REGIME_PATHS},
    /* fog: lit from above from -18 up to 0.2 + 2.8, the day's column above */
    {"fog, sun -18", {FOG(7.8, 200.0)}, 1, 0.0, -18.0, 0, FOG_LAYERS_FOG, FOG_REGIME_FROM_ABOVE},
    {"fog, sun -18.01", {FOG(7.8, 200.0)}, 1, 0.0, -18.01, 0, FOG_LAYERS_FOG, FOG_REGIME_PATHS},
    {"fog, sun 2.99", {FOG(7.8, 200.0)}, 1, 0.0, 2.99, 0, FOG_LAYERS_FOG, FOG_REGIME_FROM_ABOVE},
    {"fog, sun 3.01", {FOG(7.8, 200.0)}, 1, 0.0, 3.01, 0, FOG_LAYERS_FOG, FOG_REGIME_DAY},
    {"fog, sun 1, twilight tables", {FOG(7.8, 200.0)}, 1, 0.0, 1.0, TWILIGHT, FOG_LAYERS_FOG, FOG_REGIME_FROM_ABOVE},
    {"fog, sun 30, reference", {FOG(7.8, 200.0)}, 1, 0.0, 30.0, REFERENCE, FOG_LAYERS_FOG, FOG_REGIME_PATHS},
    {"fog, no light from above, sun 0.21", {FOG(7.8, 200.0)}, 1, 0.0, 0.21, FROM_ABOVE_OFF, FOG_LAYERS_FOG,
     FOG_REGIME_DAY},
    {"fog, no light from above, sun 0.19", {FOG(7.8, 200.0)}, 1, 0.0, 0.19, FROM_ABOVE_OFF, FOG_LAYERS_FOG,
     FOG_REGIME_PATHS},
    /* on the ground: below 0.5 m */
    {"fog, observer at 0.49 m, sun 1", {FOG(7.8, 200.0)}, 1, 0.49, 1.0, 0, FOG_LAYERS_FOG, FOG_REGIME_FROM_ABOVE},
    {"fog, observer at 0.5 m, sun 1", {FOG(7.8, 200.0)}, 1, 0.5, 1.0, 0, FOG_LAYERS_FOG, FOG_REGIME_DAY},
    /* shallow fog: optical depth 0.8 to 2, the day's column from sun 6 */
    {"shallow fog, sun 6.01", {FOG(0.98, 100.0)}, 1, 0.0, 6.01, 0, FOG_LAYERS_SHALLOW_FOG, FOG_REGIME_DAY},
    {"shallow fog, sun 5.99", {FOG(0.98, 100.0)}, 1, 0.0, 5.99, 0, FOG_LAYERS_SHALLOW_FOG, FOG_REGIME_PATHS},
    {"shallow fog, sun 2.99", {FOG(0.98, 100.0)}, 1, 0.0, 2.99, 0, FOG_LAYERS_SHALLOW_FOG, FOG_REGIME_FROM_ABOVE},
    {"fog of 1.99, sun 5.99", {FOG(1.99, 200.0)}, 1, 0.0, 5.99, 0, FOG_LAYERS_SHALLOW_FOG, FOG_REGIME_PATHS},
    {"fog of 2, sun 5.99", {FOG(2.0, 200.0)}, 1, 0.0, 5.99, 0, FOG_LAYERS_FOG, FOG_REGIME_DAY},
    {"fog of 0.8, sun 10", {FOG(0.8, 200.0)}, 1, 0.0, 10.0, 0, FOG_LAYERS_SHALLOW_FOG, FOG_REGIME_DAY},
    /* thinner fog: from sun 24 */
    {"fog of 0.79, sun 10", {FOG(0.79, 200.0)}, 1, 0.0, 10.0, 0, FOG_LAYERS_THIN_FOG, FOG_REGIME_PATHS},
    {"fog of 0.79, sun 24.01", {FOG(0.79, 200.0)}, 1, 0.0, 24.01, 0, FOG_LAYERS_THIN_FOG, FOG_REGIME_DAY},
    {"fog of 0.79, sun 23.99", {FOG(0.79, 200.0)}, 1, 0.0, 23.99, 0, FOG_LAYERS_THIN_FOG, FOG_REGIME_PATHS},
    /* a deck: 1 degree per km of its base (3 + 2.8 lit from above), several suns above a 1 km base */
    {"altostratus, sun 5.79", {AS}, 1, 0.0, 5.79, 0, FOG_LAYERS_DECK, FOG_REGIME_FROM_ABOVE_SUNS},
    {"altostratus, sun 5.81", {AS}, 1, 0.0, 5.81, 0, FOG_LAYERS_DECK, FOG_REGIME_DAY},
    {"altostratus, no light from above, sun 3.01", {AS}, 1, 0.0, 3.01, FROM_ABOVE_OFF, FOG_LAYERS_DECK,
     FOG_REGIME_DAY},
    {"altostratus, no light from above, sun 2.99", {AS}, 1, 0.0, 2.99, FROM_ABOVE_OFF, FOG_LAYERS_DECK,
     FOG_REGIME_PATHS},
    {"deck at 1000 m, sun 2", {WATER(1000.0, 500.0, 10.0)}, 1, 0.0, 2.0, 0, FOG_LAYERS_DECK, FOG_REGIME_FROM_ABOVE},
    {"deck at 1001 m, sun 2", {WATER(1001.0, 500.0, 10.0)}, 1, 0.0, 2.0, 0, FOG_LAYERS_DECK,
     FOG_REGIME_FROM_ABOVE_SUNS},
    {"deck of 2, sun 10", {WATER(3000.0, 1000.0, 2.0)}, 1, 0.0, 10.0, 0, FOG_LAYERS_DECK, FOG_REGIME_DAY},
    /* a thin water layer: from sun 24 */
    {"altostratus of 1.99, sun 10", {WATER(3000.0, 1000.0, 1.99)}, 1, 0.0, 10.0, 0, FOG_LAYERS_THIN, FOG_REGIME_PATHS},
    {"altostratus of 1, sun 24.01", {WATER(3000.0, 1000.0, 1.0)}, 1, 0.0, 24.01, 0, FOG_LAYERS_THIN, FOG_REGIME_DAY},
    {"altostratus of 1, sun 23.99", {WATER(3000.0, 1000.0, 1.0)}, 1, 0.0, 23.99, 0, FOG_LAYERS_THIN, FOG_REGIME_PATHS},
    {"altostratus of 0.1, sun 30", {WATER(3000.0, 1000.0, 0.1)}, 1, 0.0, 30.0, 0, FOG_LAYERS_THIN, FOG_REGIME_DAY},
    {"altostratus of 0.099, sun 30", {WATER(3000.0, 1000.0, 0.099)}, 1, 0.0, 30.0, 0, FOG_LAYERS_NONE,
     FOG_REGIME_PATHS},
    /* above a deck: several suns below 10, 1 degree per km of its base */
    {"above a deck, sun 9.99", {WATER(1000.0, 500.0, 10.0)}, 1, 3000.0, 9.99, 0, FOG_LAYERS_DECK_BELOW,
     FOG_REGIME_DAY_ABOVE_SUNS},
    {"above a deck, sun 10.01", {WATER(1000.0, 500.0, 10.0)}, 1, 3000.0, 10.01, 0, FOG_LAYERS_DECK_BELOW,
     FOG_REGIME_DAY},
    {"above a deck, sun 1.01", {WATER(1000.0, 500.0, 10.0)}, 1, 3000.0, 1.01, 0, FOG_LAYERS_DECK_BELOW,
     FOG_REGIME_DAY_ABOVE_SUNS},
    {"above a deck, sun 0.99", {WATER(1000.0, 500.0, 10.0)}, 1, 3000.0, 0.99, 0, FOG_LAYERS_DECK_BELOW,
     FOG_REGIME_PATHS},
    /* thin layers above a deck: as the deck alone where lit from above, else from sun 8 */
    {"cirrostratus over altostratus, sun 5.79", {AS, CS}, 2, 0.0, 5.79, 0, FOG_LAYERS_DECK_UNDER_THIN,
     FOG_REGIME_FROM_ABOVE_SUNS},
    {"cirrostratus over altostratus, sun 5.81", {AS, CS}, 2, 0.0, 5.81, 0, FOG_LAYERS_DECK_UNDER_THIN, FOG_REGIME_DAY},
    {"cirrostratus over altostratus, no light from above, sun 7.99", {AS, CS}, 2, 0.0, 7.99, FROM_ABOVE_OFF,
     FOG_LAYERS_DECK_UNDER_THIN, FOG_REGIME_PATHS},
    {"cirrostratus over altostratus, no light from above, sun 8.01", {AS, CS}, 2, 0.0, 8.01, FROM_ABOVE_OFF,
     FOG_LAYERS_DECK_UNDER_THIN, FOG_REGIME_DAY},
    {"cirrostratus over altostratus, observer at 500 m, sun 7.99", {AS, CS}, 2, 500.0, 7.99, 0,
     FOG_LAYERS_DECK_UNDER_THIN, FOG_REGIME_PATHS},
    /* shallow fog under thin layers: lit from above from 5, blended up to 12 + 2.8 */
    {"fog under cirrostratus, sun 4.99", {FOG(0.98, 100.0), CS}, 2, 0.0, 4.99, 0, FOG_LAYERS_FOG_UNDER_THIN,
     FOG_REGIME_PATHS},
    {"fog under cirrostratus, sun 5", {FOG(0.98, 100.0), CS}, 2, 0.0, 5.0, 0, FOG_LAYERS_FOG_UNDER_THIN,
     FOG_REGIME_FROM_ABOVE},
    {"fog under cirrostratus, sun 14.79", {FOG(0.98, 100.0), CS}, 2, 0.0, 14.79, 0, FOG_LAYERS_FOG_UNDER_THIN,
     FOG_REGIME_FROM_ABOVE},
    {"fog under cirrostratus, sun 14.81", {FOG(0.98, 100.0), CS}, 2, 0.0, 14.81, 0, FOG_LAYERS_FOG_UNDER_THIN,
     FOG_REGIME_DAY},
    {"fog under cirrostratus, no light from above, sun 14.79", {FOG(0.98, 100.0), CS}, 2, 0.0, 14.79,
     FROM_ABOVE_OFF, FOG_LAYERS_FOG_UNDER_THIN, FOG_REGIME_PATHS},
    /* other layers with a thick one (or fog of 2): from sun 8; with thin fog, 24 */
    {"fog of 2 under cirrostratus, sun 8.01", {FOG(2.0, 200.0), CS}, 2, 0.0, 8.01, 0, FOG_LAYERS_MIXED,
     FOG_REGIME_DAY},
    {"fog of 2 under cirrostratus, sun 7.99", {FOG(2.0, 200.0), CS}, 2, 0.0, 7.99, 0, FOG_LAYERS_MIXED,
     FOG_REGIME_PATHS},
    {"stratocumulus under altostratus, sun 8.01", {WATER(1000.0, 500.0, 10.0), AS}, 2, 0.0, 8.01, 0, FOG_LAYERS_MIXED,
     FOG_REGIME_DAY},
    {"stratocumulus under altostratus, sun 7.99", {WATER(1000.0, 500.0, 10.0), AS}, 2, 0.0, 7.99, 0, FOG_LAYERS_MIXED,
     FOG_REGIME_PATHS},
    {"fog of 0.79 under cirrostratus, sun 23.99", {FOG(0.79, 200.0), CS}, 2, 0.0, 23.99, 0, FOG_LAYERS_THIN,
     FOG_REGIME_PATHS},
    /* a thin layer of ice alone: several suns from 1 (optical depth 1 or more) or 3, one from 24 */
    {"cirrostratus, sun 1.01", {CS}, 1, 0.0, 1.01, 0, FOG_LAYERS_THIN_ICE, FOG_REGIME_DAY_THIN_SUNS},
    {"cirrostratus, sun 0.99", {CS}, 1, 0.0, 0.99, 0, FOG_LAYERS_THIN_ICE, FOG_REGIME_PATHS},
    {"cirrostratus, sun 23.99", {CS}, 1, 0.0, 23.99, 0, FOG_LAYERS_THIN_ICE, FOG_REGIME_DAY_THIN_SUNS},
    {"cirrostratus, sun 24.01", {CS}, 1, 0.0, 24.01, 0, FOG_LAYERS_THIN_ICE, FOG_REGIME_DAY},
    {"cirrostratus, sun 24.01, twilight tables", {CS}, 1, 0.0, 24.01, TWILIGHT, FOG_LAYERS_THIN_ICE, FOG_REGIME_PATHS},
    {"cirrostratus of 0.99, sun 3.01", {ICE(8000.0, 1500.0, 0.99)}, 1, 0.0, 3.01, 0, FOG_LAYERS_THIN_ICE_VEIL,
     FOG_REGIME_DAY_THIN_SUNS},
    {"cirrostratus of 0.99, sun 2.99", {ICE(8000.0, 1500.0, 0.99)}, 1, 0.0, 2.99, 0, FOG_LAYERS_THIN_ICE_VEIL,
     FOG_REGIME_PATHS},
    {"cirrostratus, observer at 0.5 m, sun 10", {CS}, 1, 0.5, 10.0, 0, FOG_LAYERS_THIN, FOG_REGIME_PATHS},
};

static fog_scene scene_of(const regime_case *c)
{
    fog_scene s = {.layer_count = c->layers,
                   .altitude_m = c->altitude_m,
                   .sun_z = sin(c->sun_deg * FM_DEG),
                   .fog_from_above = !(c->flags & FROM_ABOVE_OFF),
                   .twilight = !!(c->flags & TWILIGHT),
                   .reference = !!(c->flags & REFERENCE)};
    for (int i = 0; i < c->layers; i++)
        s.layer[i] = c->layer[i];
    return s;
}

static void each_case_takes_its_regime(void **state)
{
    (void)state;
    int wrong = 0, seen[FOG_LAYERS_COUNT] = {0};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const fog_scene s = scene_of(&cases[i]);
        int cloud;
        const fog_layers row = fog_scene_layers(&s, &cloud);
        const fog_regime regime = fog_scene_regime(&s);
        seen[row] = 1;
        if (row != cases[i].row || regime != cases[i].regime) {
            printf("%s: layers %d (want %d), regime %d (want %d)\n", cases[i].what, row, cases[i].row, regime,
                   cases[i].regime);
            wrong++;
        }
    }
    assert_int_equal(wrong, 0);
    for (int r = 0; r < FOG_LAYERS_COUNT; r++) /* every row of the table has a case */
        assert_true(seen[r]);
}

/* The column lit from above's share: 1 below its row's bound, 0 above the blend, linear between. */
static void the_share_falls_across_the_blend(void **state)
{
    (void)state;
    const struct {
        regime_case c;
        double share;
    } shares[] = {
        {{"fog, sun 0.1", {FOG(7.8, 200.0)}, 1, 0.0, 0.1, 0, 0, 0}, 1.0},
        {{"fog, sun 1.6", {FOG(7.8, 200.0)}, 1, 0.0, 1.6, 0, 0, 0}, 0.5},
        {{"altostratus, sun 4.4", {AS}, 1, 0.0, 4.4, 0, 0, 0}, 0.5},
        {{"fog under cirrostratus, sun 11.9", {FOG(0.98, 100.0), CS}, 2, 0.0, 11.9, 0, 0, 0}, 1.0},
        {{"fog under cirrostratus, sun 13.4", {FOG(0.98, 100.0), CS}, 2, 0.0, 13.4, 0, 0, 0}, 0.5},
        {{"fog under cirrostratus, sun 14.9", {FOG(0.98, 100.0), CS}, 2, 0.0, 14.9, 0, 0, 0}, 0.0},
    };
    for (size_t i = 0; i < sizeof shares / sizeof shares[0]; i++) {
        const fog_scene s = scene_of(&shares[i].c);
        check_abs(fog_scene_above_share(&s), shares[i].share, 1e-9, shares[i].c.what);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(each_case_takes_its_regime),
        cmocka_unit_test(the_share_falls_across_the_blend),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
