#include "camera/fisheye.h"

#include "base/quadrature.h"
#include "base/units.h"

#include <math.h>

void fisheye_init(fisheye *f, int size, int equisolid)
{
    f->size = size;
    f->radius_px = 0.5 * size;
    f->equisolid = equisolid;
}

double fisheye_theta(const fisheye *f, double rho)
{
    if (f->equisolid)
        return acos(clamp_cosine(1.0 - rho * rho));
    return 0.5 * FM_PI * rho;
}

double fisheye_rho(const fisheye *f, double theta)
{
    if (f->equisolid)
        return sqrt(2.0) * sin(0.5 * theta);
    return theta / (0.5 * FM_PI);
}

/* Normalised image-plane coordinates, Y up: the circle is X^2 + Y^2 = 1. */
static void normalised(const fisheye *f, double x, double y, double *X, double *Y)
{
    *X = (x - f->radius_px) / f->radius_px;
    *Y = (f->radius_px - y) / f->radius_px;
}

int fisheye_direction(const fisheye *f, double x, double y, vec3 *d)
{
    double X, Y;
    normalised(f, x, y, &X, &Y);
    fisheye_sample(f, x, y, d);
    return X * X + Y * Y <= 1.0;
}

double fisheye_sample(const fisheye *f, double x, double y, vec3 *d)
{
    double X, Y;
    normalised(f, x, y, &X, &Y);
    double rho2 = X * X + Y * Y, rho = sqrt(rho2);
    double theta = fisheye_theta(f, rho), s = sin(theta), c = cos(theta);
    /* east (a = 90 deg) to the left: X = -rho sin a, Y = rho cos a */
    *d = rho > 0.0 ? v3(-X * s / rho, Y * s / rho, c) : v3(0.0, 0.0, 1.0);
    if (rho > 1.0)
        return 0.0;
    /* solid angle per unit normalised area, (sin theta / rho) d theta / d rho, per square pixel */
    double j = f->equisolid ? 2.0 : (rho > 1e-12 ? 0.5 * FM_PI * s / rho : 0.25 * FM_PI * FM_PI);
    return j / (f->radius_px * f->radius_px);
}

int fisheye_project(const fisheye *f, vec3 d, double *x, double *y)
{
    double len = v3_length(d);
    if (!(len > 0.0))
        return 0;
    double h = hypot(d.x, d.y);
    double theta = atan2(h, d.z);
    if (h == 0.0 && d.z < 0.0)
        return 0; /* the nadir: every azimuth */
    double rho = fisheye_rho(f, theta);
    double X = h > 0.0 ? -rho * d.x / h : 0.0, Y = h > 0.0 ? rho * d.y / h : 0.0;
    *x = f->radius_px * (1.0 + X);
    *y = f->radius_px * (1.0 - Y);
    return 1;
}

/* Solid angle per unit normalised area at rho: (sin theta / rho) d theta / d rho. */
static double jacobian_normalised(const fisheye *f, double rho)
{
    if (f->equisolid)
        return 2.0;
    const double k = 0.5 * FM_PI;
    return rho > 1e-12 ? k * sin(k * rho) / rho : k * k;
}

double fisheye_jacobian(const fisheye *f, double x, double y)
{
    double X, Y;
    normalised(f, x, y, &X, &Y);
    double rho = hypot(X, Y);
    if (rho > 1.0)
        return 0.0;
    return jacobian_normalised(f, rho) / (f->radius_px * f->radius_px);
}

/* Green's theorem.  For a weight j(rho) per unit normalised area, the 1-form G(rho) dphi with
 * G(rho) = integral_0^rho j(s) s ds satisfies d(G dphi) = j dA, so the integral of j over a region is
 * the integral of G dphi counterclockwise around its boundary.  For dOmega, G = 1 - cos theta; for
 * cos theta dOmega, G = sin^2 theta / 2.  Along a straight edge P(t) = A + t D,
 * dphi = (P x D) / |P|^2 dt = (A x D) / |P|^2 dt, and G / rho^2 is smooth (analytic in rho^2), so
 * Gauss-Legendre integrates each edge to rounding; along the circle G is constant and the integral
 * is G(1) times the angle swept.  The region is the pixel square clipped to the unit disk. */
static double g_over_rho2(const fisheye *f, double rho2, int cosine)
{
    if (f->equisolid) /* 1 - cos theta = rho^2 */
        return cosine ? 0.5 * (2.0 - rho2) : 1.0;
    const double k = 0.5 * FM_PI;
    double rho = sqrt(rho2);
    if (rho < 1e-12)
        return 0.5 * k * k; /* both limits */
    if (cosine) {
        double s = sin(k * rho) / rho;
        return 0.5 * s * s;
    }
    double s = sin(0.5 * k * rho) / rho; /* 1 - cos(k rho) = 2 sin^2(k rho / 2) */
    return 2.0 * s * s;
}

#define EDGE_POINTS 16

static double edge_integral(const fisheye *f, double ax, double ay, double bx, double by, int cosine)
{
    double dx = bx - ax, dy = by - ay, dd = dx * dx + dy * dy;
    double cross = ax * dy - ay * dx;
    /* the chord of the unit circle on this line, from the line's distance to the centre, |cross| / |D|
     * (exactly 1 for the image's edges, tangent to the circle: no chord, where the quadratic formula
     * would leave one of rounding size) */
    double chord2 = 1.0 - cross * cross / dd;
    if (!(chord2 > 0.0) || cross == 0.0)
        return 0.0;
    double mid_t = -(ax * dx + ay * dy) / dd, half_t = sqrt(chord2 / dd);
    double t0 = fmax(0.0, mid_t - half_t), t1 = fmin(1.0, mid_t + half_t);
    if (!(t1 > t0))
        return 0.0;
    const gauss_rule *g = gauss_legendre_cached(EDGE_POINTS);
    double sum = 0.0, half = 0.5 * (t1 - t0), mid = 0.5 * (t1 + t0);
    for (int i = 0; i < g->n; i++) {
        double t = mid + half * g->x[i];
        double px = ax + t * dx, py = ay + t * dy;
        sum += g->w[i] * g_over_rho2(f, px * px + py * py, cosine);
    }
    return sum * half * cross;
}

/* Angle (rad) of the unit circle's arcs inside the rectangle [x0, x1] x [y0, y1]. */
static double arcs_inside(double x0, double x1, double y0, double y1)
{
    double angles[10];
    int n = 0;
    double xs[2] = {x0, x1}, ys[2] = {y0, y1};
    for (int i = 0; i < 2; i++) {
        if (fabs(xs[i]) < 1.0) { /* the circle meets the vertical line x = xs[i] at y = +-h */
            double h = sqrt(1.0 - xs[i] * xs[i]);
            for (int s = -1; s <= 1; s += 2)
                if (s * h >= y0 && s * h <= y1)
                    angles[n++] = atan2(s * h, xs[i]);
        }
        if (fabs(ys[i]) < 1.0) {
            double w = sqrt(1.0 - ys[i] * ys[i]);
            for (int s = -1; s <= 1; s += 2)
                if (s * w >= x0 && s * w <= x1)
                    angles[n++] = atan2(ys[i], s * w);
        }
    }
    if (n == 0)
        return 0.0; /* a pixel never contains the whole circle */
    for (int i = 1; i < n; i++) /* insertion sort */
        for (int j = i; j > 0 && angles[j] < angles[j - 1]; j--) {
            double t = angles[j];
            angles[j] = angles[j - 1];
            angles[j - 1] = t;
        }
    double total = 0.0;
    for (int i = 0; i < n; i++) {
        double a0 = angles[i], a1 = i + 1 < n ? angles[i + 1] : angles[0] + 2.0 * FM_PI;
        double am = 0.5 * (a0 + a1), cx = cos(am), cy = sin(am);
        if (cx > x0 && cx < x1 && cy > y0 && cy < y1)
            total += a1 - a0;
    }
    return total;
}

/* A pixel wholly inside the circle: the integrand is smooth over it, and 3 x 3 Gauss-Legendre points
 * (exact for degree 5 in each variable) are as good as the boundary integral, at a seventh of the cost;
 * the cosine-weighted integral, summed over every pixel for the sidecar, takes 2 x 2 (its sum over a
 * 30-pixel image is off by 1.2e-7, falling as the fourth power of the pixel size). */
static double interior_integral(const fisheye *f, double x0, double x1, double y0, double y1, int cosine)
{
    const int n = cosine ? 2 : 3;
    const gauss_rule *g = gauss_legendre_cached(n);
    double hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0), sum = 0.0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double X = 0.5 * (x0 + x1) + hx * g->x[i], Y = 0.5 * (y0 + y1) + hy * g->x[j];
            double rho2 = X * X + Y * Y, v;
            if (f->equisolid) /* j = 2, cos theta = 1 - rho^2 */
                v = cosine ? 2.0 * (1.0 - rho2) : 2.0;
            else if (cosine) /* j cos theta = (pi/2) sin(k rho) cos(k rho) / rho = (pi/4) sin(2 k rho) / rho */
                v = rho2 > 1e-24 ? 0.25 * FM_PI * sin(FM_PI * sqrt(rho2)) / sqrt(rho2) : 0.25 * FM_PI * FM_PI;
            else
                v = jacobian_normalised(f, sqrt(rho2));
            sum += g->w[i] * g->w[j] * v;
        }
    return sum * hx * hy;
}

double fisheye_pixel_integral(const fisheye *f, int px, int py, int cosine)
{
    double x0, x1, y0, y1; /* normalised, Y up */
    normalised(f, px, py + 1, &x0, &y0);
    normalised(f, px + 1, py, &x1, &y1);
    double far_x = fmax(fabs(x0), fabs(x1)), far_y = fmax(fabs(y0), fabs(y1));
    if (far_x * far_x + far_y * far_y < 1.0)
        return interior_integral(f, x0, x1, y0, y1, cosine);
    /* counterclockwise: bottom, right, top, left edges */
    double sum = edge_integral(f, x0, y0, x1, y0, cosine) + edge_integral(f, x1, y0, x1, y1, cosine) +
                 edge_integral(f, x1, y1, x0, y1, cosine) + edge_integral(f, x0, y1, x0, y0, cosine);
    double g1 = cosine ? 0.5 : 1.0; /* G on the circle (theta = 90 degrees) */
    return sum + g1 * arcs_inside(x0, x1, y0, y1);
}

int fisheye_column_span(const fisheye *f, double x, double y0, double y1, double *lo, double *hi)
{
    double X = (x - f->radius_px) / f->radius_px;
    if (fabs(X) >= 1.0)
        return 0;
    double h = f->radius_px * sqrt(1.0 - X * X); /* the circle spans R -+ h in y */
    *lo = fmax(y0, f->radius_px - h);
    *hi = fmin(y1, f->radius_px + h);
    return *hi > *lo;
}
