#include "colour/colour.h"

#include <math.h>
#include <pthread.h>

const double fm_rec709_to_xyz[3][3] = {
    {0.4124564, 0.3575761, 0.1804375},
    {0.2126729, 0.7151522, 0.0721750},
    {0.0193339, 0.1191920, 0.9503041},
};

const float fm_rec709_chromaticities[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

static double xyz_to_rec709[3][3];
static pthread_once_t inverse_once = PTHREAD_ONCE_INIT;

void colour_matrix_inverse(const double *m9, double inv[3][3])
{
    const double(*m)[3] = (const double(*)[3])m9;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            /* cofactor of m[j][i] */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    }
}

void colour_matrix_apply(const double *m9, const double in[3], double out[3])
{
    const double(*m)[3] = (const double(*)[3])m9;
    for (int i = 0; i < 3; i++)
        out[i] = m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2];
}

int colour_matrix_from_chromaticities(const float c[8], double m[3][3])
{
    if (c[0] == 1.0f && c[1] == 0.0f && c[2] == 0.0f && c[3] == 1.0f && c[4] == 0.0f && c[5] == 0.0f) {
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                m[i][j] = i == j;
        return 1;
    }
    double p[3][3], inv[3][3], w[3], s[3];
    for (int k = 0; k < 4; k++)
        if (!(c[2 * k + 1] > 0.0f))
            return 0;
    for (int k = 0; k < 3; k++) { /* column k: XYZ of primary k with Y = 1 */
        double x = c[2 * k], y = c[2 * k + 1];
        p[0][k] = x / y, p[1][k] = 1.0, p[2][k] = (1.0 - x - y) / y;
    }
    double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                 p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    if (fabs(det) < 1e-9)
        return 0;
    colour_matrix_inverse(&p[0][0], inv);
    w[0] = c[6] / c[7], w[1] = 1.0, w[2] = (1.0 - c[6] - c[7]) / c[7];
    colour_matrix_apply(&inv[0][0], w, s);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[i][j] = p[i][j] * s[j];
    return 1;
}

/* The inverse is computed from the forward matrix so the round trip is exact to rounding. */
static void compute_inverse(void)
{
    const double (*m)[3] = fm_rec709_to_xyz;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            /* cofactor of m[j][i] */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            xyz_to_rec709[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    }
}

void colour_xyz_to_rec709(const double xyz[3], double rgb[3])
{
    pthread_once(&inverse_once, compute_inverse);
    for (int i = 0; i < 3; i++)
        rgb[i] = xyz_to_rec709[i][0] * xyz[0] + xyz_to_rec709[i][1] * xyz[1] + xyz_to_rec709[i][2] * xyz[2];
}

void colour_rec709_to_xyz(const double rgb[3], double xyz[3])
{
    for (int i = 0; i < 3; i++)
        xyz[i] = fm_rec709_to_xyz[i][0] * rgb[0] + fm_rec709_to_xyz[i][1] * rgb[1] + fm_rec709_to_xyz[i][2] * rgb[2];
}
