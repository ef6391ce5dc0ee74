#include "atmosphere/standard_atmosphere.h"

#include <math.h>
#include <pthread.h>

/* Constants as defined by the standard (US76, Table 2 and section 1.2). */
#define US76_G0 9.80665          /* m s^-2 */
#define US76_M0 28.9644e-3       /* kg mol^-1 */
#define US76_RSTAR 8.31432       /* J mol^-1 K^-1 */
#define US76_AVOGADRO 6.022169e23 /* mol^-1 */
#define US76_R0 6356766.0        /* m, effective Earth radius for geopotential altitude */
#define US76_T0 288.15           /* K */
#define US76_P0 101325.0         /* Pa */

/* Layer bases in geopotential metres and temperature gradients in K per geopotential metre. */
static const double layer_base_m[] = {0.0, 11000.0, 20000.0, 32000.0, 47000.0, 51000.0, 71000.0, 84852.0};
static const double lapse_k_per_m[] = {-6.5e-3, 0.0, 1.0e-3, 2.8e-3, 0.0, -2.8e-3, -2.0e-3, 0.0};
#define US76_LAYERS 8

typedef struct layer_state {
    double base_t, base_p;
} layer_state;

/* Temperature and pressure at each layer base, computed once from the sea-level values. */
static layer_state layer_states[US76_LAYERS];
static pthread_once_t layers_once = PTHREAD_ONCE_INIT;

static double layer_pressure(int i, double t_base, double p_base, double h)
{
    double dh = h - layer_base_m[i];
    double l = lapse_k_per_m[i];
    double k = US76_G0 * US76_M0 / US76_RSTAR;
    if (l == 0.0)
        return p_base * exp(-k * dh / t_base);
    return p_base * pow(t_base / (t_base + l * dh), k / l);
}

static void init_layers(void)
{
    double t = US76_T0, p = US76_P0;
    for (int i = 0; i < US76_LAYERS; i++) {
        layer_states[i].base_t = t;
        layer_states[i].base_p = p;
        if (i + 1 < US76_LAYERS) {
            double top = layer_base_m[i + 1];
            p = layer_pressure(i, t, p, top);
            t = t + lapse_k_per_m[i] * (top - layer_base_m[i]);
        }
    }
}

static double geopotential_m(double z)
{
    return US76_R0 * z / (US76_R0 + z);
}

static int layer_of(double h)
{
    int i = US76_LAYERS - 1;
    while (i > 0 && h < layer_base_m[i])
        i--;
    return i;
}

double us76_temperature_k(double altitude_m)
{
    pthread_once(&layers_once, init_layers);
    double h = geopotential_m(altitude_m);
    int i = layer_of(h);
    return layer_states[i].base_t + lapse_k_per_m[i] * (h - layer_base_m[i]);
}

double us76_pressure_pa(double altitude_m)
{
    pthread_once(&layers_once, init_layers);
    double h = geopotential_m(altitude_m);
    int i = layer_of(h);
    return layer_pressure(i, layer_states[i].base_t, layer_states[i].base_p, h);
}

double us76_number_density(double altitude_m)
{
    return us76_pressure_pa(altitude_m) * US76_AVOGADRO / (US76_RSTAR * us76_temperature_k(altitude_m));
}
